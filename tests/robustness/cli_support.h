#pragma once
// Runs the envshadow executable (ENVSHADOW_EXE) in a folder and checks the error contract of
// docs/DESIGN.md §6: exit code 2 (usage) or 3 (input), exactly one line on stderr naming the file or
// option, and nothing left behind in the folder: no output file, no temporary.
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_files.h"

namespace envshadow::test {

struct CliRun {
    int exit_code = -1;  // 128 + signal when killed by one
    std::string out, err;
};

// Runs `envshadow args...` with `folder` as working directory, killed after `timeout_seconds`.
inline CliRun run_envshadow(const std::vector<std::string>& args, const std::filesystem::path& folder,
                            int timeout_seconds = 60) {
    const std::filesystem::path out = folder / ".stdout", err = folder / ".stderr";
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (::chdir(folder.c_str()) != 0) ::_exit(120);
        const int out_fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int err_fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (out_fd < 0 || err_fd < 0 || ::dup2(out_fd, 1) < 0 || ::dup2(err_fd, 2) < 0) ::_exit(121);
        ::alarm(unsigned(timeout_seconds));  // survives exec: a hang ends in SIGALRM
        std::vector<char*> argv;
        std::string exe = ENVSHADOW_EXE;
        argv.push_back(exe.data());
        std::vector<std::string> copies = args;
        for (std::string& a : copies) argv.push_back(a.data());
        argv.push_back(nullptr);
        ::execv(exe.c_str(), argv.data());
        ::_exit(122);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    CliRun run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    run.out = read_text(out);
    run.err = read_text(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return run;
}

inline std::string describe(const std::vector<std::string>& args, const CliRun& run) {
    std::string text = "envshadow";
    for (const std::string& a : args) text += " " + a;
    return text + "\n  exit " + std::to_string(run.exit_code) + "\n  stderr: " + run.err + "  stdout: " + run.out;
}

// Exit code `code`, and stderr one line that contains every string in `named`.
inline ::testing::AssertionResult fails_with(const CliRun& run, int code, const std::vector<std::string>& named) {
    if (run.exit_code != code)
        return ::testing::AssertionFailure() << "exit code " << run.exit_code << ", not " << code;
    if (run.err.empty() || run.err.back() != '\n' || std::count(run.err.begin(), run.err.end(), '\n') != 1)
        return ::testing::AssertionFailure() << "stderr is not exactly one line: [" << run.err << "]";
    for (const std::string& n : named)
        if (run.err.find(n) == std::string::npos)
            return ::testing::AssertionFailure() << "stderr does not name " << n << ": " << run.err;
    return ::testing::AssertionSuccess();
}

// The names in `folder` (recursively, hidden ones included).
inline std::set<std::string> files_in(const std::filesystem::path& folder) {
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
        names.insert(std::filesystem::relative(entry.path(), folder).string());
    return names;
}

}  // namespace envshadow::test
