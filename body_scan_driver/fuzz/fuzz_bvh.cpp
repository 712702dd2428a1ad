// libFuzzer entry point of the BVH reader (make fuzz). Any input must either parse into a
// consistent motion or throw BvhError; anything else (a crash, another exception, a sanitizer
// report, a motion whose frames do not match its channels) is a finding. test_bvh runs this same
// function over the seed corpus, so a finding turned into a seed stays fixed.
#include <body_scan_driver/sim/bvh.h>

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace body_scan_driver::sim;
  const std::string text(reinterpret_cast<const char*>(data), size);
  BvhMotion motion;
  try {
    motion = parseBvh(text, "<fuzz>");
  } catch (const BvhError&) {
    return 0;
  }
  int channels = 0;
  for (size_t j = 0; j < motion.joints.size(); ++j) {
    const BvhJoint& joint = motion.joints[j];
    if (joint.parent >= int(j) || joint.first_channel != channels) std::abort();
    channels += int(joint.channels.size());
  }
  if (channels != motion.channel_count || motion.frames.empty() || !(motion.frame_time > 0))
    std::abort();
  for (const auto& frame : motion.frames)
    if (int(frame.size()) != motion.channel_count) std::abort();
  // Posing must work on every frame of an accepted file (first and last suffice for the fuzzer).
  poseBvhFrame(motion, 0);
  poseBvhFrame(motion, int(motion.frames.size()) - 1);
  return 0;
}
