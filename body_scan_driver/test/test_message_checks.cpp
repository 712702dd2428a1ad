// The message checks name the field that is wrong, and pass every message our own nodes publish.
#include <body_scan_driver/ros/conversions.h>
#include <body_scan_driver/ros/message_checks.h>
#include <gtest/gtest.h>

using namespace body_scan_driver;

namespace {

sensor_msgs::Image image(uint32_t width, uint32_t height, const std::string& encoding) {
  sensor_msgs::Image out;
  out.width = width, out.height = height, out.encoding = encoding;
  out.step = width * (encoding == "rgb8" ? 3 : 1);
  out.data.assign(static_cast<size_t>(out.step) * height, 0);
  return out;
}

// A valid 8-bit set with inverses (18 frames) of 8x6 images.
body_scan_msgs::PatternSet goodSet() {
  body_scan_msgs::PatternSet set;
  set.header.frame_id = "pole_a/pair_1_camera_optical_frame";
  set.pair_id = "pole_a/pair_1";
  set.scheme = "gray";
  set.bits = 8;
  set.inverse_frames = true;
  set.texture = image(8, 6, "rgb8");
  set.frames.assign(18, image(8, 6, "mono8"));
  return set;
}

// Expects a problem that mentions `field`.
void expectProblem(const MessageProblem& problem, const std::string& field) {
  ASSERT_TRUE(problem) << "accepted; expected a problem with " << field;
  EXPECT_NE(problem->find(field), std::string::npos) << *problem;
}

TEST(MessageChecks, PatternSet) {
  EXPECT_FALSE(checkPatternSet(goodSet()));
  auto set = goodSet();
  set.frames[0].step = 7;  // row step smaller than the width: cv::Mat would throw
  expectProblem(checkPatternSet(set), "frames[0].step");
  set = goodSet();
  set.frames[5].data.resize(47);
  expectProblem(checkPatternSet(set), "frames[5].data");
  set = goodSet();
  set.frames[3].encoding = "rgb8";
  expectProblem(checkPatternSet(set), "frames[3].encoding");
  set = goodSet();
  set.frames[17] = image(9, 6, "mono8");
  expectProblem(checkPatternSet(set), "frames[17]");
  set = goodSet();
  set.frames.pop_back();
  expectProblem(checkPatternSet(set), "frames holds 17");
  set = goodSet();
  set.bits = 0;
  expectProblem(checkPatternSet(set), "bits 0");
  set = goodSet();
  set.bits = 200;
  expectProblem(checkPatternSet(set), "bits 200");
  set = goodSet();
  set.scheme = "phase";
  expectProblem(checkPatternSet(set), "scheme");
  set = goodSet();
  set.frames[1].width = 0;
  expectProblem(checkPatternSet(set), "frames[1] is 0x6");
  set = goodSet();
  set.texture.step = 3;
  expectProblem(checkPatternSet(set), "texture.step");
  set = goodSet();
  set.texture = image(4, 3, "rgb8");
  expectProblem(checkPatternSet(set), "texture is 4x3");
  set = goodSet();
  set.texture = sensor_msgs::Image();  // no texture is allowed
  EXPECT_FALSE(checkPatternSet(set));
  set = goodSet();
  set.header.frame_id = "";
  expectProblem(checkPatternSet(set), "header.frame_id");
  set = goodSet();
  set.pair_id = "";
  expectProblem(checkPatternSet(set), "pair_id");
  // Steps near 2^32: no overflow lets a short buffer through.
  set = goodSet();
  set.frames[2].step = 0xFFFFFFFFu;
  expectProblem(checkPatternSet(set), "frames[2].data");
}

TEST(MessageChecks, PairCloud) {
  body_scan_msgs::PairCloud part;
  part.pair_id = "pole_a/pair_1";
  part.cloud.header.frame_id = "pole_a/pair_1_camera_optical_frame";
  layoutFloatCloud(part.cloud, 8, 6, /*rgb=*/true);
  EXPECT_FALSE(checkPairCloud(part));
  auto bad = part;
  bad.cloud.data.pop_back();
  expectProblem(checkPairCloud(bad), "cloud.data");
  bad = part;
  bad.cloud.row_step = 8;
  expectProblem(checkPairCloud(bad), "cloud.row_step");
  bad = part;
  bad.cloud.point_step = 6;
  expectProblem(checkPairCloud(bad), "cloud.point_step");
  bad = part;
  bad.cloud.fields[1].offset = 8;
  expectProblem(checkPairCloud(bad), "cloud.fields 'y'");
  bad = part;
  bad.cloud.fields.erase(bad.cloud.fields.begin() + 2);
  expectProblem(checkPairCloud(bad), "no 'z'");
  bad = part;
  bad.cloud.fields[3].offset = 16;
  expectProblem(checkPairCloud(bad), "'rgb'");
  bad = part;
  bad.cloud.is_bigendian = true;
  expectProblem(checkPairCloud(bad), "is_bigendian");
  bad = part;
  bad.cloud.header.frame_id = "a b";
  expectProblem(checkPairCloud(bad), "cloud.header.frame_id");
  bad = part;
  bad.pair_id.clear();
  expectProblem(checkPairCloud(bad), "pair_id");
  bad = part;
  bad.cloud.width = 0x40000000u;  // width x point_step overflows 32 bits
  bad.cloud.row_step = bad.cloud.width * bad.cloud.point_step;
  expectProblem(checkPairCloud(bad), "cloud.row_step");
}

TEST(MessageChecks, TimingGroups) {
  body_scan_msgs::TimingGroups groups;
  groups.groups = {"pole_a/pair_1 pole_b/pair_1", "pole_a/pair_2"};
  groups.group_seconds = 0.5;
  EXPECT_FALSE(checkTimingGroups(groups));
  auto bad = groups;
  bad.group_seconds = std::nan("");
  expectProblem(checkTimingGroups(bad), "group_seconds");
  bad = groups;
  bad.groups[1] = " ";
  expectProblem(checkTimingGroups(bad), "groups[1]");
}

}  // namespace

namespace {

TEST(MessageChecks, ThrottleReportsEachProblemOncePerPeriod) {
  ProblemThrottle throttle(5.0);
  EXPECT_TRUE(throttle.shouldReport("frames[0].step", 100.0));
  EXPECT_FALSE(throttle.shouldReport("frames[0].step", 104.9));
  EXPECT_TRUE(throttle.shouldReport("bits 0", 104.9));  // another problem: at once
  EXPECT_TRUE(throttle.shouldReport("frames[0].step", 105.1));
  EXPECT_FALSE(throttle.shouldReport("frames[0].step", 106.0));
}

}  // namespace
