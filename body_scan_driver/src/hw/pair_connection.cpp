#include <body_scan_driver/hw/pair_connection.h>

#include <algorithm>
#include <exception>
#include <stdexcept>

namespace body_scan_driver::hw {

const char* toString(ConnectionState state) {
  switch (state) {
    case ConnectionState::kDisconnected:
      return "DISCONNECTED";
    case ConnectionState::kConnected:
      return "CONNECTED";
    case ConnectionState::kStreaming:
      return "STREAMING";
    case ConnectionState::kError:
      return "ERROR";
  }
  return "?";
}

PairConnection::PairConnection(Hooks hooks, RetryPolicy policy)
    : hooks_(std::move(hooks)), policy_(policy) {
  if (!hooks_.open || !hooks_.start_streaming || !hooks_.close)
    throw std::invalid_argument("PairConnection needs open, start_streaming and close hooks");
  if (policy_.initial_interval_s <= 0 || policy_.growth_factor < 1 ||
      policy_.max_interval_s < policy_.initial_interval_s)
    throw std::invalid_argument(
        "retry policy: need initial interval > 0, growth factor >= 1 and max >= initial");
}

void PairConnection::poll(double now_s) {
  if (state_ == ConnectionState::kStreaming) return;
  if (state_ == ConnectionState::kError && now_s < next_attempt_s_) return;
  ++total_attempts_;
  try {
    if (state_ != ConnectionState::kConnected) {
      hooks_.open();
      state_ = ConnectionState::kConnected;
    }
    hooks_.start_streaming();
    state_ = ConnectionState::kStreaming;
    failed_attempts_ = 0;
    retry_interval_s_ = 0;
    last_error_.clear();
  } catch (const std::exception& e) {
    fail(e.what(), now_s);
  }
}

void PairConnection::reportFailure(const std::string& reason, double now_s) { fail(reason, now_s); }

void PairConnection::deviceArrived() {
  if (state_ != ConnectionState::kError) return;
  next_attempt_s_ = 0;
  failed_attempts_ = 0;
  retry_interval_s_ = 0;
}

void PairConnection::disconnect() {
  hooks_.close();
  state_ = ConnectionState::kDisconnected;
}

void PairConnection::fail(const std::string& reason, double now_s) {
  hooks_.close();  // a half-open device is reopened from scratch
  state_ = ConnectionState::kError;
  last_error_ = reason;
  ++failed_attempts_;
  retry_interval_s_ = failed_attempts_ == 1 ? policy_.initial_interval_s
                                            : std::min(retry_interval_s_ * policy_.growth_factor,
                                                       policy_.max_interval_s);
  next_attempt_s_ = now_s + retry_interval_s_;
}

}  // namespace body_scan_driver::hw
