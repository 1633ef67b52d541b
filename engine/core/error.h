#pragma once
// Errors that cross the engine's boundary. Inside the engine values are trusted; at the boundary
// (files, command line, GL context creation) a failure becomes one of these, with a one-line message
// that names the file or option and the reason. app/main.cpp maps them to exit codes.
#include <stdexcept>
#include <string>

namespace envshadow {

// Bad input data: a file that is missing, truncated, corrupt, non-finite or out of limits. Exit code 3.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A bad command-line value or combination. Exit code 2.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The platform cannot do what was asked (no GL context, a GPU limit exceeded). Exit code 4.
class PlatformError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace envshadow
