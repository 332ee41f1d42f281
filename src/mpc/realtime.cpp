#include "idto/mpc/realtime.hpp"

#include <cstring>
#include <string>

#include <pthread.h>
#include <sched.h>

#include "core/parallel.hpp"
#include "idto/core/errors.hpp"

namespace idto::mpc {
namespace {

std::string Refusal(const std::string& who, int priority, int error) {
  return who + " could not take SCHED_FIFO priority " + std::to_string(priority) +
         " (pthread_setschedparam: " + std::strerror(error) +
         "); it needs root, CAP_SYS_NICE or an RLIMIT_RTPRIO (ulimit -r) of at least " +
         std::to_string(priority) + ", and a container that allows real-time scheduling";
}

}  // namespace

RealtimeScheduling::RealtimeScheduling(int priority) : priority_(priority) {
  if (priority == 0) return;
  if (priority < 1 || priority > kMaxRealtimePriority) {
    ThrowInvalidArgument(
        "RealtimeScheduling", "priority", std::to_string(priority),
        "0 (off) or a SCHED_FIFO priority in [1, " + std::to_string(kMaxRealtimePriority) + "]");
  }
  sched_param old{};
  if (pthread_getschedparam(pthread_self(), &old_policy_, &old) != 0) {
    error_ = "the loop's thread could not read its scheduling";
    return;
  }
  old_priority_ = old.sched_priority;
  sched_param param{};
  param.sched_priority = priority;
  const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (error != 0) {
    error_ = Refusal("the loop's thread", priority, error);
    return;
  }
  active_ = true;
  internal::TakeThreadPoolSchedulingError();  // refusals before this scope are not ours
  internal::SetThreadPoolScheduling(SCHED_FIFO, priority);
}

RealtimeScheduling::~RealtimeScheduling() {
  if (!active_) return;
  sched_param param{};
  param.sched_priority = old_priority_;
  pthread_setschedparam(pthread_self(), old_policy_, &param);
  internal::SetThreadPoolScheduling(old_policy_, old_priority_);
}

const std::string& RealtimeScheduling::CheckWorkers() {
  if (!active_) return error_;
  const int error = internal::TakeThreadPoolSchedulingError();
  if (error != 0 && error_.empty()) error_ = Refusal("a solver worker thread", priority_, error);
  return error_;
}

}  // namespace idto::mpc
