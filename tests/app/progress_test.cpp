// The progress line of long commands: its text, that it is written only where asked (a terminal)
// and erased at the end; and `envshadow reference` stopped by SIGINT exits 130 having written
// nothing, its output to a pipe carrying no progress line.
#include "progress.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

namespace envshadow::app {
namespace {

namespace fs = std::filesystem;

TEST(ProgressLine, SaysHowFarHowLongAndHowLongIsLeft) {
    EXPECT_EQ(ProgressLine::format("reference", "rows", 25, 100, 10.0),
              "reference: 25% (25/100 rows), 10 s, about 30 s left");
    EXPECT_EQ(ProgressLine::format("reference", "rows", 0, 100, 2.0), "reference: 0% (0/100 rows), 2 s");
    EXPECT_EQ(ProgressLine::format("cases", "cases", 7, 7, 61.0), "cases: 100% (7/7 cases), 61 s");
}

std::string written_by(bool enabled) {
    std::FILE* file = std::tmpfile();
    {
        ProgressLine line("reference", "rows", file, enabled);
        line.update(1, 4);
        line.update(4, 4);  // the last update is shown even within the quarter second
    }
    std::rewind(file);
    std::string text;
    for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) text += char(c);
    std::fclose(file);
    return text;
}

TEST(ProgressLine, RewritesOneLineAndErasesItOnlyWhenEnabled) {
    EXPECT_EQ(written_by(false), "");
    const std::string text = written_by(true);
    EXPECT_EQ(text,
              "\r\033[Kreference: 25% (1/4 rows), 0 s, about 0 s left\r\033[Kreference: 100% (4/4 rows), 0 s\r\033[K");
    EXPECT_EQ(text.find('\n'), std::string::npos);  // one line, rewritten in place
}

// Whether process `pid` has a handler installed for `signal` (Linux: SigCgt in /proc/PID/status).
bool catches(pid_t pid, int signal) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (signal - 1)) & 1;
    return false;
}

TEST(ReferenceCommand, CtrlCStopsItWithNothingWritten) {
    const fs::path dir = fs::path(::testing::TempDir()) / "envshadow_progress" / "interrupt";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path exr = dir / "out.exr", log = dir / "log.txt";
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::freopen(log.c_str(), "w", stdout);
        std::freopen(log.c_str(), "a", stderr);
        // Big enough to run for minutes here: it must be stopped, not finish.
        execl(ENVSHADOW_EXE, ENVSHADOW_EXE, "reference", "--scene", ENVSHADOW_SOURCE_DIR "/assets/scenes/default.json",
              "--width", "640", "--height", "360", "--error", "0.001", "--exr", exr.c_str(), "--png",
              (dir / "out.png").c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    // Signal only once its handler is in: before that SIGINT would just kill it (a different test).
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!catches(pid, SIGINT) && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_TRUE(catches(pid, SIGINT)) << "the reference never installed its SIGINT handler";
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    std::ifstream text(log);
    std::stringstream out;
    out << text.rdbuf();
    ASSERT_TRUE(WIFEXITED(status)) << out.str();
    EXPECT_EQ(WEXITSTATUS(status), 130) << out.str();
    EXPECT_NE(out.str().find("interrupted, nothing written"), std::string::npos) << out.str();
    EXPECT_EQ(out.str().find('\r'), std::string::npos) << "progress written to a file: " << out.str();
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path(), log) << "left behind: " << entry.path();
}

}  // namespace
}  // namespace envshadow::app
