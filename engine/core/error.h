#pragma once
// Errors that cross the engine's boundary. Inside the engine values are trusted; at the boundary
// (files, command line, GL context creation) a failure becomes one of these, with a one-line message
// that names the file or option and the reason. app/main.cpp maps them to exit codes.
#include <cstdio>
#include <stdexcept>
#include <string>

namespace envshadow {

// `text` with control characters written as \n, \r, \t or \xHH: messages quote keys, names and
// paths taken from files and the command line, and must stay one line whatever those contain.
inline std::string one_line_text(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u != 0x7f) {
            out += c;
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02x", u);
            out += hex;
        }
    }
    return out;
}

// Bad input data: a file that is missing, truncated, corrupt, non-finite or out of limits. Exit code 3.
class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(one_line_text(message)) {}
};

// A bad command-line value or combination. Exit code 2.
class UsageError : public std::runtime_error {
public:
    explicit UsageError(const std::string& message) : std::runtime_error(one_line_text(message)) {}
};

// The platform cannot do what was asked (no GL context, a GPU limit exceeded). Exit code 4.
class PlatformError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The user asked to stop (Ctrl-C) before the work was done; nothing was written. Exit code 130.
class Interrupted : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace envshadow
