// The connection state machine with fake hooks and a fake clock.
#include <body_scan_driver/hw/pair_connection.h>
#include <gtest/gtest.h>

#include <stdexcept>

using namespace body_scan_driver::hw;

namespace {

struct FakeDevice {
  bool present = false, streams = true;
  int opens = 0, starts = 0, closes = 0;
  PairConnection::Hooks hooks() {
    return {[this] {
              ++opens;
              if (!present) throw std::runtime_error("camera 1234:5678/NOSUCHCAM not found");
            },
            [this] {
              ++starts;
              if (!streams) throw std::runtime_error("no stream");
            },
            [this] { ++closes; }};
  }
};

const RetryPolicy kPolicy{0.5, 2.0, 4.0};

}  // namespace

TEST(PairConnection, StartsDisconnectedAndStreamsOnFirstPollWhenTheDeviceIsThere) {
  FakeDevice device;
  device.present = true;
  PairConnection connection(device.hooks(), kPolicy);
  EXPECT_EQ(connection.state(), ConnectionState::kDisconnected);
  connection.poll(0.0);
  EXPECT_EQ(connection.state(), ConnectionState::kStreaming);
  EXPECT_EQ(device.opens, 1);
  EXPECT_EQ(device.starts, 1);
  connection.poll(1.0);  // streaming: nothing to do
  EXPECT_EQ(device.opens, 1);
}

TEST(PairConnection, MissingDeviceRetriesWithGrowingIntervalUpToTheMaximum) {
  FakeDevice device;
  PairConnection connection(device.hooks(), kPolicy);
  double now = 0;
  std::vector<double> intervals;
  for (int attempt = 0; attempt < 6; ++attempt) {
    connection.poll(now);
    EXPECT_EQ(connection.state(), ConnectionState::kError);
    EXPECT_EQ(connection.lastError(), "camera 1234:5678/NOSUCHCAM not found");
    EXPECT_EQ(device.opens, attempt + 1);
    intervals.push_back(connection.retryInterval());
    // Not due yet: no attempt.
    connection.poll(connection.nextAttemptAt() - 0.01);
    EXPECT_EQ(device.opens, attempt + 1);
    now = connection.nextAttemptAt();
  }
  EXPECT_EQ(intervals, (std::vector<double>{0.5, 1.0, 2.0, 4.0, 4.0, 4.0}));
  EXPECT_EQ(connection.failedAttempts(), 6);
  EXPECT_EQ(device.closes, 6);  // every failed attempt releases what it opened

  device.present = true;
  connection.poll(now);
  EXPECT_EQ(connection.state(), ConnectionState::kStreaming);
  EXPECT_EQ(connection.failedAttempts(), 0);
  EXPECT_TRUE(connection.lastError().empty());
}

TEST(PairConnection, StreamStartFailureClosesAndReopensFromScratch) {
  FakeDevice device;
  device.present = true;
  device.streams = false;
  PairConnection connection(device.hooks(), kPolicy);
  connection.poll(0.0);
  EXPECT_EQ(connection.state(), ConnectionState::kError);
  EXPECT_EQ(device.closes, 1);
  device.streams = true;
  connection.poll(0.5);
  EXPECT_EQ(connection.state(), ConnectionState::kStreaming);
  EXPECT_EQ(device.opens, 2);
}

TEST(PairConnection, FailureWhileStreamingReconnectsAfterTheInitialInterval) {
  FakeDevice device;
  device.present = true;
  PairConnection connection(device.hooks(), kPolicy);
  connection.poll(0.0);
  connection.reportFailure("frame timeout", 10.0);
  EXPECT_EQ(connection.state(), ConnectionState::kError);
  EXPECT_EQ(connection.lastError(), "frame timeout");
  EXPECT_DOUBLE_EQ(connection.nextAttemptAt(), 10.5);
  connection.poll(10.4);
  EXPECT_EQ(connection.state(), ConnectionState::kError);
  connection.poll(10.5);
  EXPECT_EQ(connection.state(), ConnectionState::kStreaming);
}

TEST(PairConnection, HotplugArrivalRetriesAtOnce) {
  FakeDevice device;
  PairConnection connection(device.hooks(), kPolicy);
  for (double now : {0.0, 0.5, 1.5, 3.5}) connection.poll(now);
  ASSERT_DOUBLE_EQ(connection.nextAttemptAt(), 7.5);
  device.present = true;
  connection.deviceArrived();
  connection.poll(3.6);
  EXPECT_EQ(connection.state(), ConnectionState::kStreaming);
}

TEST(PairConnection, DisconnectStopsUntilPolledAgain) {
  FakeDevice device;
  device.present = true;
  PairConnection connection(device.hooks(), kPolicy);
  connection.poll(0.0);
  connection.disconnect();
  EXPECT_EQ(connection.state(), ConnectionState::kDisconnected);
  EXPECT_EQ(device.closes, 1);
}

TEST(PairConnection, RejectsAPolicyThatCannotWork) {
  FakeDevice device;
  EXPECT_THROW(PairConnection(device.hooks(), RetryPolicy{0.0, 2.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(PairConnection(device.hooks(), RetryPolicy{1.0, 0.5, 2.0}), std::invalid_argument);
  EXPECT_THROW(PairConnection(device.hooks(), RetryPolicy{1.0, 2.0, 0.5}), std::invalid_argument);
}
