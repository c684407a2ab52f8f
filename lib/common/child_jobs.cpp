#include "common/child_jobs.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <thread>
#include <vector>

namespace weft::jobs {
namespace {

using Clock = std::chrono::steady_clock;

struct Child {
    pid_t pid = -1;
    int fd = -1;
    size_t index = 0;
    std::string output;
    Clock::time_point start;
};

void write_all(int fd, const std::string& text) {
    for (size_t done = 0; done < text.size();) {
        const ssize_t n = write(fd, text.data() + done, text.size() - done);
        if (n <= 0) return;
        done += size_t(n);
    }
}

// Forks a child that runs work(index) and writes its string to a pipe.
Child start_child(size_t index, const std::function<std::string(size_t)>& work) {
    Child c;
    c.index = index;
    c.start = Clock::now();
    int fds[2];
    if (pipe(fds) != 0) return c;
    std::fflush(stdout), std::fflush(stderr);
    c.pid = fork();
    if (c.pid == 0) {  // the child: work, write, leave without running the parent's exit handlers
        close(fds[0]);
        int status = 0;
        try {
            write_all(fds[1], work(index));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "exception: %s\n", e.what());
            status = 2;
        }
        std::fflush(stdout), std::fflush(stderr);
        _exit(status);
    }
    close(fds[1]);
    if (c.pid < 0) {
        close(fds[0]);
        return c;
    }
    c.fd = fds[0];
    return c;
}

Outcome finish_child(Child& c, bool timed_out) {
    if (timed_out) kill(c.pid, SIGKILL);
    int status = 0;
    waitpid(c.pid, &status, 0);
    close(c.fd);
    Outcome o;
    o.output = std::move(c.output);
    if (timed_out)
        o.error = "timed out";
    else if (WIFSIGNALED(status))
        o.error = std::string("crashed: ") + strsignal(WTERMSIG(status));
    else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        o.error = "no result (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
    return o;
}

}  // namespace

uint32_t every_core() { return std::max(1u, std::thread::hardware_concurrency()); }

void run_in_children(size_t count, const Options& options, const std::function<std::string(size_t)>& work,
                     const std::function<void(size_t, Outcome)>& done) {
    const uint32_t jobs = options.jobs > 0 ? options.jobs : every_core();
    std::vector<Child> running;
    size_t next = 0;
    while (next < count || !running.empty()) {
        while (running.size() < jobs && next < count) {
            Child c = start_child(next, work);
            if (c.pid < 0)
                done(next, Outcome{{}, "cannot start a process"});
            else
                running.push_back(std::move(c));
            ++next;
        }
        if (running.empty()) continue;
        std::vector<pollfd> fds;
        for (const Child& c : running) fds.push_back({c.fd, POLLIN, 0});
        poll(fds.data(), fds.size(), 200);
        for (size_t k = running.size(); k-- > 0;) {
            Child& c = running[k];
            bool ended = false;
            if (fds[k].revents & (POLLIN | POLLHUP | POLLERR)) {
                char buffer[4096];
                const ssize_t n = read(c.fd, buffer, sizeof buffer);
                if (n > 0) c.output.append(buffer, size_t(n));
                ended = n <= 0;
            }
            const bool timed_out = !ended && options.timeout_s > 0.0 &&
                                   std::chrono::duration<double>(Clock::now() - c.start).count() > options.timeout_s;
            if (!ended && !timed_out) continue;
            const size_t index = c.index;
            Outcome outcome = finish_child(c, timed_out);
            running.erase(running.begin() + std::ptrdiff_t(k));
            done(index, std::move(outcome));
        }
    }
}

}  // namespace weft::jobs
