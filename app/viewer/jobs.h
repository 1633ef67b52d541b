#pragma once
// Work the viewer runs off the render thread (loading maps and models, decomposing), polled once
// a frame so that the window never waits for it.
#include <chrono>
#include <exception>
#include <future>
#include <optional>
#include <string>
#include <utility>

namespace envshadow::app {

template <class T>
class BackgroundJob {
public:
    template <class F>
    void start(std::string what, F&& work) {
        what_ = std::move(what);
        started_ = std::chrono::steady_clock::now();
        future_ = std::async(std::launch::async, std::forward<F>(work));
    }
    bool running() const { return future_.valid(); }
    const std::string& what() const { return what_; }
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    }

    // The result once ready (then the job is idle again); a failure's message goes to `error`.
    std::optional<T> poll(std::string& error) {
        if (!future_.valid() || future_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
            return std::nullopt;
        try {
            return future_.get();
        } catch (const std::exception& e) {
            error = e.what();
            return std::nullopt;
        }
    }

    // Blocks until the job is done (automated runs that must show its result); as poll otherwise.
    std::optional<T> wait(std::string& error) {
        if (future_.valid()) future_.wait();
        return poll(error);
    }

private:
    std::future<T> future_;
    std::string what_;
    std::chrono::steady_clock::time_point started_;
};

}  // namespace envshadow::app
