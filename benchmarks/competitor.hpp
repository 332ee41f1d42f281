#pragma once

// A busy competitor process for the contention benchmarks: a child process that spins on one
// core, as another program on the machine would. It can be paused (SIGSTOP) and resumed
// (SIGCONT) so quiet and contended measurements alternate within one run, and it is killed
// (SIGKILL, then reaped) when the object is destroyed. The child also dies with its parent
// (PR_SET_PDEATHSIG), so an interrupted benchmark leaves no spinning process behind. It runs in a
// session of its own, so the scheduler treats it as another program, not as part of the benchmark.

#include <csignal>
#include <stdexcept>
#include <string>

#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

namespace idto::bench {

class BusyCompetitor {
 public:
  /// Starts the spinning child, paused when `running` is false.
  explicit BusyCompetitor(bool running) {
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("BusyCompetitor: fork failed");
    if (pid_ == 0) Spin(parent);
    running_ = true;
    if (!running) Pause();
  }
  BusyCompetitor(const BusyCompetitor&) = delete;
  BusyCompetitor& operator=(const BusyCompetitor&) = delete;
  ~BusyCompetitor() {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
  }

  /// Stops the child (SIGSTOP): the machine is as quiet as without it.
  void Pause() {
    if (!running_) return;
    kill(pid_, SIGSTOP);
    WaitFor(WUNTRACED);
    running_ = false;
  }

  /// Lets the child spin again (SIGCONT).
  void Resume() {
    if (running_) return;
    kill(pid_, SIGCONT);
    WaitFor(WCONTINUED);
    running_ = true;
  }

  pid_t pid() const { return pid_; }

 private:
  // The child: only async-signal-safe calls after fork() (the parent has threads).
  [[noreturn]] static void Spin(pid_t parent) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(0);  // the parent died before prctl
    // Its own session: with the kernel's session autogroups (sched_autogroup_enabled) a child in
    // the benchmark's session would only compete inside the benchmark's share of the CPU.
    setsid();
    volatile unsigned long counter = 0;
    for (;;) counter = counter + 1;
  }

  // Waits until the child reports the state change asked for by `option`.
  void WaitFor(int option) {
    int status = 0;
    if (waitpid(pid_, &status, option) != pid_) {
      throw std::runtime_error("BusyCompetitor: waitpid failed");
    }
  }

  pid_t pid_{-1};
  bool running_{false};
};

}  // namespace idto::bench
