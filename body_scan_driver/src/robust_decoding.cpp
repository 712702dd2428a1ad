#include <body_scan_driver/robust_decoding.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace body_scan_driver {

namespace {

// The pixel is left undecoded (both of StripeImage's outputs).
void invalidate(StripeImage& stripes, int v, int u) {
  stripes.coordinate(v, u) = std::numeric_limits<float>::quiet_NaN();
  stripes.stripe(v, u) = kInvalidStripe;
}

}  // namespace

bool stripesChangeAlongRows(const cv::Mat1f& coordinate, int sample_step) {
  double along_rows = 0, along_columns = 0;
  for (int v = 0; v + 1 < coordinate.rows; v += sample_step)
    for (int u = 0; u + 1 < coordinate.cols; u += sample_step) {
      const float c = coordinate(v, u), below = coordinate(v + 1, u), right = coordinate(v, u + 1);
      if (std::isfinite(c) && std::isfinite(below) && std::abs(below - c) < 2)
        along_rows += std::abs(below - c);
      if (std::isfinite(c) && std::isfinite(right) && std::abs(right - c) < 2)
        along_columns += std::abs(right - c);
    }
  return along_rows >= along_columns;
}

DecoderParams RobustDecoding::decoderParams(DecoderParams params) const {
  if (enabled) {
    params.min_contrast = min_contrast;
    params.edge_contrast_ratio = edge_contrast_ratio;
  }
  return params;
}

size_t rejectInconsistentCodes(StripeImage& stripes, const RobustDecoding& robust) {
  constexpr int kRadius = 2;
  const cv::Mat1f source = stripes.coordinate.clone();
  size_t rejected = 0;
  std::vector<float> window;
  window.reserve((2 * kRadius + 1) * (2 * kRadius + 1));
  for (int v = 0; v < source.rows; ++v)
    for (int u = 0; u < source.cols; ++u) {
      const float centre = source(v, u);
      if (!std::isfinite(centre)) continue;
      window.clear();
      for (int dv = -kRadius; dv <= kRadius; ++dv)
        for (int du = -kRadius; du <= kRadius; ++du) {
          const int y = v + dv, x = u + du;
          if ((dv || du) && y >= 0 && y < source.rows && x >= 0 && x < source.cols &&
              std::isfinite(source(y, x)))
            window.push_back(source(y, x));
        }
      bool consistent = static_cast<int>(window.size()) >= robust.min_neighbours;
      if (consistent) {
        std::nth_element(window.begin(), window.begin() + window.size() / 2, window.end());
        consistent = std::abs(centre - window[window.size() / 2]) <= robust.max_neighbour_deviation;
      }
      if (consistent) continue;
      invalidate(stripes, v, u);
      ++rejected;
    }
  return rejected;
}

namespace {

// Box sum of m over the fit window (zero outside the image).
cv::Mat1d windowSum(const cv::Mat1d& m, cv::Size window) {
  cv::Mat1d sum;
  cv::boxFilter(m, sum, CV_64F, window, cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  return sum;
}

}  // namespace

size_t fitLocalPlanes(StripeImage& stripes, const std::vector<cv::Mat>& frames,
                      const RobustDecoding& robust) {
  if (robust.fit_radius_along <= 0 && robust.fit_radius_across <= 0) return 0;
  cv::Mat contrast;
  cv::subtract(frames[PatternLayout::litFrame()], frames[PatternLayout::darkFrame()], contrast);
  const bool along_rows = stripesChangeAlongRows(stripes.coordinate, 2);
  // Stripes change along rows: the stripe runs along the image row (u), across is v.
  const int half_u = along_rows ? robust.fit_radius_along : robust.fit_radius_across;
  const int half_v = along_rows ? robust.fit_radius_across : robust.fit_radius_along;
  const cv::Size window(2 * half_u + 1, 2 * half_v + 1);
  const int rows = stripes.coordinate.rows, cols = stripes.coordinate.cols;
  const cv::Mat1f measured = stripes.coordinate.clone();
  // Inverse noise variance: a bit's signal scales with the contrast, its noise does not.
  cv::Mat1d weight(rows, cols, 0.0), u_image(rows, cols), v_image(rows, cols),
      s_image(rows, cols, 0.0);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      u_image(v, u) = u;
      v_image(v, u) = v;
      if (!std::isfinite(measured(v, u))) continue;
      const double c = std::max(1, static_cast<int>(contrast.at<uint8_t>(v, u)));
      weight(v, u) = c * c;
      s_image(v, u) = measured(v, u);
    }
  const cv::Mat1d measured_weight = weight.clone();
  cv::Mat1f fitted(rows, cols, std::numeric_limits<float>::quiet_NaN());
  cv::Mat1d weight_sum;
  for (int pass = 0; pass < robust.fit_passes; ++pass) {
    const cv::Mat1d wu = weight.mul(u_image), wv = weight.mul(v_image), ws = weight.mul(s_image);
    weight_sum = windowSum(weight, window);
    const cv::Mat1d su = windowSum(wu, window), sv = windowSum(wv, window),
                    suu = windowSum(wu.mul(u_image), window),
                    suv = windowSum(wu.mul(v_image), window),
                    svv = windowSum(wv.mul(v_image), window), ss = windowSum(ws, window),
                    sus = windowSum(wu.mul(s_image), window),
                    svs = windowSum(wv.mul(s_image), window);
    for (int v = 0; v < rows; ++v)
      for (int u = 0; u < cols; ++u) {
        fitted(v, u) = std::numeric_limits<float>::quiet_NaN();
        const double w = weight_sum(v, u);
        if (!std::isfinite(measured(v, u)) || w <= 0) continue;
        // Weighted least squares s = mean + g . (x - centroid) from centred moments.
        const double mu = su(v, u) / w, mv = sv(v, u) / w, ms = ss(v, u) / w;
        const double cuu = suu(v, u) / w - mu * mu, cuv = suv(v, u) / w - mu * mv,
                     cvv = svv(v, u) / w - mv * mv;
        const double cus = sus(v, u) / w - mu * ms, cvs = svs(v, u) / w - mv * ms;
        const double det = cuu * cvv - cuv * cuv;
        double gu = 0, gv = 0;
        if (det > 1e-6 * (cuu + cvv) * (cuu + cvv)) {
          gu = (cvv * cus - cuv * cvs) / det;
          gv = (cuu * cvs - cuv * cus) / det;
        } else if (cuu >= cvv && cuu > 1e-9) {
          gu = cus / cuu;  // one line of support (e.g. a band one pixel high)
        } else if (cvv > 1e-9) {
          gv = cvs / cvv;
        }
        fitted(v, u) = static_cast<float>(ms + gu * (u - mu) + gv * (v - mv));
      }
    if (pass + 1 == robust.fit_passes) break;
    for (int v = 0; v < rows; ++v)
      for (int u = 0; u < cols; ++u)
        weight(v, u) = std::abs(measured(v, u) - fitted(v, u)) <= robust.fit_outlier
                           ? measured_weight(v, u)
                           : 0.0;  // NaN comparisons are false: dropped
  }
  // The last fit's inliers per window: their mean weight is the window's typical contrast.
  cv::Mat1d inlier(rows, cols);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) inlier(v, u) = weight(v, u) > 0 ? 1.0 : 0.0;
  const cv::Mat1d inliers = windowSum(inlier, window);
  const double redecide_share = robust.redecide_contrast_share * robust.redecide_contrast_share;
  // Outliers of the last fit and how many of them each 3x3 neighbourhood holds.
  cv::Mat1d outlier(rows, cols, 0.0);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u)
      outlier(v, u) = std::abs(measured(v, u) - fitted(v, u)) > robust.fit_outlier ? 1.0 : 0.0;
  const cv::Mat1d outliers_around = windowSum(outlier, cv::Size(3, 3));
  size_t rejected = 0;
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      if (!std::isfinite(measured(v, u))) continue;
      float& coordinate = stripes.coordinate(v, u);
      coordinate = fitted(v, u);
      const double deviation = std::abs(coordinate - measured(v, u));
      // An outlier of its own window is re-decided if it is isolated (a wrong code) or its code
      // is much less reliable than its neighbours' (a dark pixel among bright ones); a run of
      // outliers as bright as their neighbours is another surface (a depth edge): blending it
      // would make flying points. A re-decision
      // moves a code by a few stripes at most (max_neighbour_deviation); farther, the window's
      // inliers lie off to one side and their plane extrapolates.
      const bool reliable_outlier =
          deviation > robust.fit_outlier && outliers_around(v, u) > robust.max_isolated_outliers &&
          measured_weight(v, u) >= redecide_share * weight_sum(v, u) / std::max(1.0, inliers(v, u));
      if (!reliable_outlier && deviation <= robust.max_neighbour_deviation) continue;
      invalidate(stripes, v, u);
      ++rejected;
    }
  return rejected;
}

size_t rejectSignalless(const std::vector<cv::Mat>& frames, const PatternLayout& layout,
                        StripeImage& stripes, const RobustDecoding& robust) {
  if (!layout.inverseFrames()) return 0;
  // The largest |pattern - inverse| over the bits: the projector's own signal at the pixel.
  cv::Mat signal = cv::Mat::zeros(frames[0].size(), CV_8U), difference;
  for (int bit = 0; bit < layout.bits(); ++bit) {
    cv::absdiff(frames[layout.patternFrame(bit)], frames[layout.inverseFrame(bit)], difference);
    signal = cv::max(signal, difference);
  }
  size_t rejected = 0;
  for (int v = 0; v < signal.rows; ++v)
    for (int u = 0; u < signal.cols; ++u)
      if (signal.at<uint8_t>(v, u) < robust.min_contrast &&
          std::isfinite(stripes.coordinate(v, u))) {
        invalidate(stripes, v, u);
        ++rejected;
      }
  return rejected;
}

void refineDecoding(const std::vector<cv::Mat>& frames, const PatternLayout& layout,
                    const std::vector<cv::Mat>& cross_frames, StripeImage& stripes,
                    const RobustDecoding& robust) {
  if (!robust.enabled) return;
  rejectSignalless(frames, layout, stripes, robust);
  rejectInconsistentCodes(stripes, robust);
  if (cross_frames.size() >= 4) {
    // The other axis's code must be decodable and locally consistent at the pixel as well.
    StripeImage cross;
    StripeDecoder(PatternLayout((static_cast<int>(cross_frames.size()) - 2) / 2, true),
                  robust.decoderParams())
        .decode(cross_frames, cross);
    rejectInconsistentCodes(cross, robust);
    for (int v = 0; v < stripes.coordinate.rows; ++v)
      for (int u = 0; u < stripes.coordinate.cols; ++u)
        if (!std::isfinite(cross.coordinate(v, u))) invalidate(stripes, v, u);
  }
  fitLocalPlanes(stripes, frames, robust);
}

StripeImage decodePatternFrames(const std::vector<cv::Mat>& frames,
                                const std::vector<cv::Mat>& cross_frames,
                                const PatternLayout& layout, const RobustDecoding& robust) {
  StripeImage stripes;
  StripeDecoder(layout, robust.decoderParams()).decode(frames, stripes);
  refineDecoding(frames, layout, cross_frames, stripes, robust);
  return stripes;
}

}  // namespace body_scan_driver
