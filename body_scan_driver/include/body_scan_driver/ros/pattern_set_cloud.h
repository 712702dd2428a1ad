// What Triangulate does with a pattern set: decode its frames, triangulate the stripe image
// with the pair's calibration (and its world alignment's residual linear part, eq 4.1), colour
// every point from the set's texture (white without one). The Triangulate nodelet and the
// PatternSet fuzz target both call this, so the fuzzer exercises exactly the nodelet's path.
#pragma once

#include <body_scan_driver/robust_decoding.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <body_scan_msgs/PatternSet.h>
#include <sensor_msgs/PointCloud2.h>

#include <memory>

namespace body_scan_driver {

// Keeps the decoder and the stripe image between sets, so a stream of sets of one layout and
// size allocates nothing but the clouds. One call at a time.
class PatternSetCloud {
 public:
  // robust.enabled: the robust decoding for real captures (robust_decoding.h) on top of params.
  explicit PatternSetCloud(const DecoderParams& params = {}, const RobustDecoding& robust = {})
      : params_(robust.decoderParams(params)), robust_(robust) {}

  // `set` must have passed checkPatternSet. Writes the organized float x y z rgb cloud of the
  // set's frame size into `cloud` (header left to the caller; NaN where nothing was measured)
  // and returns the number of valid points. Throws std::invalid_argument when the frames are
  // not the size `triangulator`'s calibration is for.
  size_t triangulate(const body_scan_msgs::PatternSet& set, const Triangulator& triangulator,
                     sensor_msgs::PointCloud2& cloud);

  // The last set's decoded stripe coordinates (stripe_image).
  const StripeImage& stripes() const { return stripes_; }

 private:
  DecoderParams params_;
  RobustDecoding robust_;
  std::unique_ptr<StripeDecoder> decoder_;  // for the last set's layout
  StripeImage stripes_;
};

}  // namespace body_scan_driver
