// Connection state machine of one hardware pair: DISCONNECTED -> CONNECTED ->
// STREAMING, any failure -> ERROR, and from ERROR a reconnect after a retry interval that
// grows with every failed attempt (so a missing device costs little but is found quickly once
// plugged in; a hot-plug arrival retries at once). Pure logic: the device is reached through
// three callbacks and time is passed in, so unit tests drive it with fakes and a fake clock.
#pragma once

#include <functional>
#include <string>

namespace body_scan_driver::hw {

enum class ConnectionState { kDisconnected, kConnected, kStreaming, kError };
const char* toString(ConnectionState state);

struct RetryPolicy {
  double initial_interval_s = 0.5;
  double growth_factor = 2.0;
  double max_interval_s = 10.0;
};

class PairConnection {
 public:
  struct Hooks {
    std::function<void()> open;             // find and open the devices; throws with the reason
    std::function<void()> start_streaming;  // start the camera; throws with the reason
    std::function<void()> close;            // release everything; must not throw
  };

  PairConnection(Hooks hooks, RetryPolicy policy);

  // Connects when a (re)connect is due at time `now_s`; otherwise does nothing.
  void poll(double now_s);
  // The streaming device failed (capture error, unplugged): close, ERROR, retry later.
  void reportFailure(const std::string& reason, double now_s);
  // A device arrived (hot-plug): the next poll() tries at once, with a fresh interval.
  void deviceArrived();
  // Close on purpose (shutdown): DISCONNECTED, no retries until poll() is called again.
  void disconnect();

  ConnectionState state() const { return state_; }
  const std::string& lastError() const { return last_error_; }
  int failedAttempts() const { return failed_attempts_; }  // since the last success
  int totalAttempts() const { return total_attempts_; }
  double retryInterval() const { return retry_interval_s_; }  // the interval now scheduled
  double nextAttemptAt() const { return next_attempt_s_; }

 private:
  void fail(const std::string& reason, double now_s);

  Hooks hooks_;
  RetryPolicy policy_;
  ConnectionState state_ = ConnectionState::kDisconnected;
  std::string last_error_;
  int failed_attempts_ = 0, total_attempts_ = 0;
  double retry_interval_s_ = 0, next_attempt_s_ = 0;
};

}  // namespace body_scan_driver::hw
