#include <body_scan_driver/triangulation.h>
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace body_scan_driver {

namespace {

#define BODY_SCAN_ALWAYS_INLINE inline __attribute__((always_inline))
#define BODY_SCAN_TARGET_AVX2 __attribute__((target("avx2")))
#define BODY_SCAN_TARGET_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq")))

struct TriangulationRows {
  const float* coordinates;
  size_t coordinate_step;
  int width, height;
  const float *rays_x, *rays_y, *planes, *deltas;
  int stripe_count;
  float min_range, max_range;
  float* out;
  size_t point_stride;
};

// x = x_n z, y = y_n z (eqs 3.10, 3.11) of one row into points of any stride.
BODY_SCAN_ALWAYS_INLINE void writePoints(const float* __restrict ray_x,
                                         const float* __restrict ray_y,
                                         const float* __restrict depth, int width,
                                         float* __restrict points, size_t point_stride) {
  for (int u = 0; u < width; ++u) {
    float* point = points + u * point_stride;
    point[0] = ray_x[u] * depth[u];
    point[1] = ray_y[u] * depth[u];
    point[2] = depth[u];
  }
}

// The same for 4-float points, 8 at a time: the 4th float of each point (rgb in a PointCloud2)
// is read and written back unchanged.
BODY_SCAN_TARGET_AVX2 void writePoints4Avx2(const float* __restrict ray_x,
                                            const float* __restrict ray_y,
                                            const float* __restrict depth, int width,
                                            float* __restrict points) {
  int u = 0;
  for (; u + 8 <= width; u += 8) {
    const __m256 z = _mm256_loadu_ps(depth + u);
    const __m256 x = _mm256_mul_ps(_mm256_loadu_ps(ray_x + u), z);
    const __m256 y = _mm256_mul_ps(_mm256_loadu_ps(ray_y + u), z);
    // Per 128-bit half: xy_low = x0 y0 x1 y1, z_low = z0 z0 z1 z1 of its first two pixels.
    const __m256 xy_low = _mm256_unpacklo_ps(x, y), xy_high = _mm256_unpackhi_ps(x, y);
    const __m256 z_low = _mm256_unpacklo_ps(z, z), z_high = _mm256_unpackhi_ps(z, z);
    // p0 = pixel 0 | pixel 4, p1 = 1 | 5, p2 = 2 | 6, p3 = 3 | 7, each (x, y, z, z).
    const __m256 p0 = _mm256_shuffle_ps(xy_low, z_low, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 p1 = _mm256_shuffle_ps(xy_low, z_low, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 p2 = _mm256_shuffle_ps(xy_high, z_high, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 p3 = _mm256_shuffle_ps(xy_high, z_high, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 pixels[4] = {
        _mm256_permute2f128_ps(p0, p1, 0x20), _mm256_permute2f128_ps(p2, p3, 0x20),
        _mm256_permute2f128_ps(p0, p1, 0x31), _mm256_permute2f128_ps(p2, p3, 0x31)};
    float* base = points + 4 * static_cast<size_t>(u);
    for (int k = 0; k < 4; ++k)  // 0x88: elements 3 and 7 keep the old 4th float
      _mm256_storeu_ps(base + 8 * k,
                       _mm256_blend_ps(pixels[k], _mm256_loadu_ps(base + 8 * k), 0x88));
  }
  writePoints(ray_x + u, ray_y + u, depth + u, width - u, points + 4 * static_cast<size_t>(u), 4);
}

// The same with AVX-512, 16 at a time: masked stores leave the 4th float alone without reading
// the cloud first (it is 4.9 MB: reading it costs DRAM bandwidth when the cloud is not cached).
BODY_SCAN_TARGET_AVX512 void writePoints4Avx512(const float* __restrict ray_x,
                                                const float* __restrict ray_y,
                                                const float* __restrict depth, int width,
                                                float* __restrict points) {
  // The maskz forms with all lanes set are the plain instructions; GCC 12 warns about the plain
  // intrinsics' _mm512_undefined_ps() operand (-Wmaybe-uninitialized).
  constexpr __mmask16 kAll = 0xFFFF;
  int u = 0;
  for (; u + 16 <= width; u += 16) {
    const __m512 z = _mm512_loadu_ps(depth + u);
    const __m512 x = _mm512_mul_ps(_mm512_loadu_ps(ray_x + u), z);
    const __m512 y = _mm512_mul_ps(_mm512_loadu_ps(ray_y + u), z);
    // As in writePoints4Avx2, per 128-bit lane: p0 = pixels 0, 4, 8, 12; p1 = 1, 5, 9, 13; ...
    const __m512 xy_low = _mm512_maskz_unpacklo_ps(kAll, x, y),
                 xy_high = _mm512_maskz_unpackhi_ps(kAll, x, y);
    const __m512 z_low = _mm512_maskz_unpacklo_ps(kAll, z, z),
                 z_high = _mm512_maskz_unpackhi_ps(kAll, z, z);
    const __m512 p0 = _mm512_maskz_shuffle_ps(kAll, xy_low, z_low, _MM_SHUFFLE(1, 0, 1, 0));
    const __m512 p1 = _mm512_maskz_shuffle_ps(kAll, xy_low, z_low, _MM_SHUFFLE(3, 2, 3, 2));
    const __m512 p2 = _mm512_maskz_shuffle_ps(kAll, xy_high, z_high, _MM_SHUFFLE(1, 0, 1, 0));
    const __m512 p3 = _mm512_maskz_shuffle_ps(kAll, xy_high, z_high, _MM_SHUFFLE(3, 2, 3, 2));
    // 4x4 transpose of 128-bit lanes: t0 = pixels 0, 4, 1, 5; t1 = 2, 6, 3, 7; t2 = 8, 12, 9,
    // 13; t3 = 10, 14, 11, 15; then 0-3, 4-7, 8-11, 12-15.
    const __m512 t0 = _mm512_maskz_shuffle_f32x4(kAll, p0, p1, 0x44),
                 t1 = _mm512_maskz_shuffle_f32x4(kAll, p2, p3, 0x44);
    const __m512 t2 = _mm512_maskz_shuffle_f32x4(kAll, p0, p1, 0xEE),
                 t3 = _mm512_maskz_shuffle_f32x4(kAll, p2, p3, 0xEE);
    float* base = points + 4 * static_cast<size_t>(u);
    constexpr __mmask16 kXyz = 0x7777;  // floats 0-2 of each point
    _mm512_mask_storeu_ps(base, kXyz, _mm512_maskz_shuffle_f32x4(kAll, t0, t1, 0x88));
    _mm512_mask_storeu_ps(base + 16, kXyz, _mm512_maskz_shuffle_f32x4(kAll, t0, t1, 0xDD));
    _mm512_mask_storeu_ps(base + 32, kXyz, _mm512_maskz_shuffle_f32x4(kAll, t2, t3, 0x88));
    _mm512_mask_storeu_ps(base + 48, kXyz, _mm512_maskz_shuffle_f32x4(kAll, t2, t3, 0xDD));
  }
  writePoints(ray_x + u, ray_y + u, depth + u, width - u, points + 4 * static_cast<size_t>(u), 4);
}

// Depth (eq 3.12) of pixels [begin, end) of one row, cut into runs of one plane index: within a
// run the plane and its slope are constants and the loop vectorizes; a NaN coordinate gives a
// NaN depth. Returns the number of depths in range.
BODY_SCAN_ALWAYS_INLINE int depthRuns(const TriangulationRows& rows, const float* __restrict s,
                                      const float* __restrict ray_x, const float* __restrict ray_y,
                                      const int* __restrict lower, float* __restrict depth,
                                      int begin, int end_of_row) {
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const float min_range = rows.min_range, max_range = rows.max_range;
  int row_valid = 0;
  for (int start = begin; start < end_of_row;) {
    int end = start + 1;
    while (end < end_of_row && lower[end] == lower[start]) ++end;
    const float* p = rows.planes + 4 * lower[start];
    const float* dp = rows.deltas + 4 * lower[start];
    const float base = static_cast<float>(lower[start]) + 0.5f;
    const float a = p[0], b = p[1], c = p[2], d = p[3];
    const float da = dp[0], db = dp[1], dc = dp[2], dd = dp[3];
    for (int u = start; u < end; ++u) {
      const float f = s[u] - base;
      const float z = -(d + f * dd) / ((a + f * da) * ray_x[u] + (b + f * db) * ray_y[u] +
                                       (c + f * dc));          // eq 3.12
      const int in_range = (z > min_range) & (z < max_range);  // 0 for NaN
      depth[u] = in_range ? z : kNaN;
      row_valid += in_range;
    }
    start = end;
  }
  return row_valid;
}

using DepthRow = int (*)(const TriangulationRows&, const float*, const float*, const float*,
                         const int*, float*);

// The same in blocks of 16 pixels: where a block's valid pixels use at most two neighbouring
// planes (most blocks: stripes cross a row rarely, but on curved surfaces often enough that runs
// are short), the plane constants are selected per lane; other blocks and the row's end take
// depthRuns. Invalid (NaN) pixels may take either plane: their depth is NaN anyway.
BODY_SCAN_TARGET_AVX512 int depthRowAvx512(const TriangulationRows& rows, const float* __restrict s,
                                           const float* __restrict ray_x,
                                           const float* __restrict ray_y,
                                           const int* __restrict lower, float* __restrict depth) {
  const int width = rows.width;
  const __m512 nan = _mm512_set1_ps(std::numeric_limits<float>::quiet_NaN());
  const __m512 min_range = _mm512_set1_ps(rows.min_range);
  const __m512 max_range = _mm512_set1_ps(rows.max_range);
  const __m512 half = _mm512_set1_ps(0.5f);
  int row_valid = 0, u = 0;
  for (; u + 16 <= width; u += 16) {
    const __m512 coordinate = _mm512_loadu_ps(s + u);
    const __mmask16 decoded = _mm512_cmp_ps_mask(coordinate, coordinate, _CMP_ORD_Q);
    if (decoded == 0) {
      _mm512_storeu_ps(depth + u, nan);
      continue;
    }
    const __m512i plane = _mm512_loadu_si512(lower + u);
    // The planes {first, first + 1} around the first decoded lane's plane, if they cover all
    // decoded lanes (mask compares: GCC 12 warns inside the reduction intrinsics).
    const int seen = lower[u + __builtin_ctz(decoded)];
    const __mmask16 on_seen = _mm512_cmpeq_epi32_mask(plane, _mm512_set1_epi32(seen));
    const __mmask16 above = _mm512_cmpeq_epi32_mask(plane, _mm512_set1_epi32(seen + 1));
    const __mmask16 below = _mm512_cmpeq_epi32_mask(plane, _mm512_set1_epi32(seen - 1));
    int first;
    if ((decoded & ~(on_seen | above)) == 0) {
      first = seen;
    } else if ((decoded & ~(on_seen | below)) == 0) {
      first = seen - 1;
    } else {
      row_valid += depthRuns(rows, s, ray_x, ray_y, lower, depth, u, u + 16);
      continue;
    }
    const int second = first + 1;  // <= stripe_count - 1: lower <= stripe_count - 2
    const __mmask16 upper = _mm512_cmpeq_epi32_mask(plane, _mm512_set1_epi32(second));
// Plane constant k of each lane (a lambda would be a function without AVX-512).
#define BODY_SCAN_PLANE_CONSTANT(table, k)                              \
  _mm512_mask_blend_ps(upper, _mm512_set1_ps((table)[4 * first + (k)]), \
                       _mm512_set1_ps((table)[4 * second + (k)]))
    const __m512 a = BODY_SCAN_PLANE_CONSTANT(rows.planes, 0);
    const __m512 b = BODY_SCAN_PLANE_CONSTANT(rows.planes, 1);
    const __m512 c = BODY_SCAN_PLANE_CONSTANT(rows.planes, 2);
    const __m512 d = BODY_SCAN_PLANE_CONSTANT(rows.planes, 3);
    const __m512 da = BODY_SCAN_PLANE_CONSTANT(rows.deltas, 0);
    const __m512 db = BODY_SCAN_PLANE_CONSTANT(rows.deltas, 1);
    const __m512 dc = BODY_SCAN_PLANE_CONSTANT(rows.deltas, 2);
    const __m512 dd = BODY_SCAN_PLANE_CONSTANT(rows.deltas, 3);
#undef BODY_SCAN_PLANE_CONSTANT
    // base = float(lower) + 0.5 per lane (NaN lanes: the first plane's, as above).
    const __m512i lane_plane =
        _mm512_mask_blend_epi32(upper, _mm512_set1_epi32(first), _mm512_set1_epi32(second));
    const __m512 base = _mm512_add_ps(_mm512_maskz_cvtepi32_ps(0xFFFF, lane_plane), half);
    const __m512 f = _mm512_sub_ps(coordinate, base);
    const __m512 numerator = _mm512_add_ps(d, _mm512_mul_ps(f, dd));
    const __m512 denominator = _mm512_add_ps(
        _mm512_add_ps(
            _mm512_mul_ps(_mm512_add_ps(a, _mm512_mul_ps(f, da)), _mm512_loadu_ps(ray_x + u)),
            _mm512_mul_ps(_mm512_add_ps(b, _mm512_mul_ps(f, db)), _mm512_loadu_ps(ray_y + u))),
        _mm512_add_ps(c, _mm512_mul_ps(f, dc)));
    const __m512 z = _mm512_div_ps(_mm512_sub_ps(_mm512_setzero_ps(), numerator), denominator);
    const __mmask16 in_range =
        _mm512_cmp_ps_mask(z, min_range, _CMP_GT_OQ) & _mm512_cmp_ps_mask(z, max_range, _CMP_LT_OQ);
    _mm512_storeu_ps(depth + u, _mm512_mask_blend_ps(in_range, nan, z));
    row_valid += __builtin_popcount(in_range);
  }
  return row_valid + depthRuns(rows, s, ray_x, ray_y, lower, depth, u, width);
}

// The per-pixel work over plain arrays, row by row: plane indices, depths, points.
BODY_SCAN_ALWAYS_INLINE size_t triangulateRows(const TriangulationRows& rows,
                                               void (*write_points4)(const float*, const float*,
                                                                     const float*, int, float*),
                                               DepthRow depth_row) {
  const int width = rows.width;
  const int last_lower = rows.stripe_count - 2;
  std::vector<float> depth_buffer(width);
  std::vector<int> lower_buffer(width);
  float* __restrict depth = depth_buffer.data();
  int* __restrict lower = lower_buffer.data();
  size_t valid = 0;
  for (int v = 0; v < rows.height; ++v) {
    const float* __restrict s = rows.coordinates + static_cast<size_t>(v) * rows.coordinate_step;
    const size_t row = static_cast<size_t>(v) * width;
    const float* __restrict ray_x = rows.rays_x + row;
    const float* __restrict ray_y = rows.rays_y + row;
    // Plane i sits at the stripe centre s = i + 0.5: pixel u interpolates planes lower[u] and
    // lower[u] + 1.
    for (int u = 0; u < width; ++u) {
      const float position = s[u] - 0.5f;  // NaN (invalid pixel) takes plane 0, depth stays NaN
      lower[u] = position > 0.f ? std::min(static_cast<int>(position), last_lower) : 0;
    }
    const int row_valid = depth_row ? depth_row(rows, s, ray_x, ray_y, lower, depth)
                                    : depthRuns(rows, s, ray_x, ray_y, lower, depth, 0, width);
    valid += static_cast<size_t>(row_valid);
    float* points = rows.out + row * rows.point_stride;
    if (write_points4 && rows.point_stride == 4) {
      write_points4(ray_x, ray_y, depth, width, points);
    } else {
      writePoints(ray_x, ray_y, depth, width, points, rows.point_stride);
    }
  }
  return valid;
}

// One body, compiled for each instruction set (simd.h); -ffp-contract=off keeps the floats equal.
size_t triangulateSse2(const TriangulationRows& rows) {
  return triangulateRows(rows, nullptr, nullptr);
}
BODY_SCAN_TARGET_AVX2 size_t triangulateAvx2(const TriangulationRows& rows) {
  return triangulateRows(rows, writePoints4Avx2, nullptr);
}
BODY_SCAN_TARGET_AVX512 size_t triangulateAvx512(const TriangulationRows& rows) {
  return triangulateRows(rows, writePoints4Avx512, depthRowAvx512);
}

}  // namespace

Triangulator::Triangulator(const PairCalibration& calibration, double min_range, double max_range,
                           SimdLevel max_simd)
    : calibration_(calibration),
      simd_(effectiveSimdLevel(max_simd)),
      min_range_(static_cast<float>(min_range)),
      max_range_(static_cast<float>(max_range)) {
  const PinholeCamera& camera = calibration.camera;
  if (calibration.projector.stripeCount() < 2)
    throw std::invalid_argument("calibration of '" + calibration.pair_id +
                                "' has fewer than 2 stripe planes");
  ray_x_.resize(static_cast<size_t>(camera.width) * camera.height);
  ray_y_.resize(ray_x_.size());
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector2d ray = camera.normalizedPoint({u, v});
      ray_x_[static_cast<size_t>(v) * camera.width + u] = static_cast<float>(ray.x());
      ray_y_[static_cast<size_t>(v) * camera.width + u] = static_cast<float>(ray.y());
    }
  const auto& planes = calibration.projector.planes;
  for (size_t k = 0; k < planes.size(); ++k)
    for (int i = 0; i < 4; ++i) {
      planes_.push_back(static_cast<float>(planes[k][i]));
      plane_deltas_.push_back(
          k + 1 < planes.size() ? static_cast<float>(planes[k + 1][i] - planes[k][i]) : 0.f);
    }
}

size_t Triangulator::triangulate(const cv::Mat1f& coordinate, float* out,
                                 size_t point_stride) const {
  const PinholeCamera& camera = calibration_.camera;
  if (coordinate.cols != camera.width || coordinate.rows != camera.height)
    throw std::invalid_argument("stripe image is " + std::to_string(coordinate.cols) + "x" +
                                std::to_string(coordinate.rows) + " but the calibration of '" +
                                calibration_.pair_id + "' is for " + std::to_string(camera.width) +
                                "x" + std::to_string(camera.height) +
                                ": use the calibration file of this camera and resolution");
  const TriangulationRows rows{coordinate.ptr<float>(),
                               coordinate.step1(),
                               camera.width,
                               camera.height,
                               ray_x_.data(),
                               ray_y_.data(),
                               planes_.data(),
                               plane_deltas_.data(),
                               calibration_.projector.stripeCount(),
                               min_range_,
                               max_range_,
                               out,
                               point_stride};
  switch (simd_) {
    case SimdLevel::kAvx512:
      return triangulateAvx512(rows);
    case SimdLevel::kAvx2:
      return triangulateAvx2(rows);
    case SimdLevel::kSse2:
      break;
  }
  return triangulateSse2(rows);
}

}  // namespace body_scan_driver
