#include <body_scan_driver/sim/virtual_pair.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

namespace body_scan_driver::sim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kSweepSamplesPerStripe = 16;
constexpr size_t kNoiseTableSize = size_t{1} << 20;  // power of two: index by mask
constexpr float kMaxFootprint = 4.f;                 // stripes; wider pixels are grazing

// Deterministic 64-bit mix (splitmix64) for noise offsets.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

cv::Vec3f toVec3f(const Eigen::Vector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

// The unit ray of pixel (u, v), clamped to the image (camera frame).
Eigen::Vector3d rayAt(const std::vector<Eigen::Vector3f>& rays, int rows, int cols, int u, int v) {
  u = std::clamp(u, 0, cols - 1);
  v = std::clamp(v, 0, rows - 1);
  return rays[static_cast<size_t>(v) * cols + u].cast<double>();
}

// Printed patterns: mean albedo and colour of the surface over 4x4 samples of the pixel area
// (left unchanged if no sample hits it). Sample rays come from the pixel's ray and its central
// differences to the neighbouring pixels' rays (distortion is smooth over a pixel; no
// per-sample undistortion).
void averageOverPixel(const Surface& surface, const std::vector<Eigen::Vector3f>& rays, int rows,
                      int cols, const Eigen::Isometry3d& pose, const Eigen::Matrix3d& rotation,
                      int u, int v, double& albedo, Eigen::Vector3d& color) {
  constexpr int kSamples = 4;
  const Eigen::Vector3d centre = rayAt(rays, rows, cols, u, v);
  const Eigen::Vector3d along_u =
      (rayAt(rays, rows, cols, u + 1, v) - rayAt(rays, rows, cols, u - 1, v)) /
      std::max(1, std::min(u + 1, cols - 1) - std::max(u - 1, 0));
  const Eigen::Vector3d along_v =
      (rayAt(rays, rows, cols, u, v + 1) - rayAt(rays, rows, cols, u, v - 1)) /
      std::max(1, std::min(v + 1, rows - 1) - std::max(v - 1, 0));
  double albedo_sum = 0;
  Eigen::Vector3d color_sum = Eigen::Vector3d::Zero();
  int hits = 0;
  for (int i = 0; i < kSamples; ++i)
    for (int j = 0; j < kSamples; ++j) {
      const double du = (j + 0.5) / kSamples - 0.5, dv = (i + 0.5) / kSamples - 0.5;
      const Eigen::Vector3d direction =
          rotation * (centre + du * along_u + dv * along_v).normalized();
      Hit sample;
      if (!surface.intersect(Ray{pose.translation(), direction}, 1e-6,
                             std::numeric_limits<double>::infinity(), sample))
        continue;
      const Eigen::Vector3d point = pose.translation() + sample.distance * direction;
      albedo_sum += surface.albedoAt(point);
      color_sum += surface.colorAt(point);
      ++hits;
    }
  if (hits == 0) return;
  albedo = albedo_sum / hits;
  color = color_sum / hits;
}

// The smaller stripe step from here to a neighbour on either side (0 if neither has a stripe).
float smallerStep(float here, float a, float b) {
  const float da = std::abs(a - here), db = std::abs(b - here);
  if (std::isnan(da)) return std::isnan(db) ? 0.f : db;
  return std::isnan(db) ? da : std::min(da, db);
}

// Which frames light each stripe: bit f of [stripe] for frame f.
std::vector<uint32_t> framesLighting(const PatternLayout& layout) {
  const int frames = layout.frameCount(), stripes = layout.stripeCount();
  if (frames > 32) throw std::logic_error("framesLighting: more than 32 frames");
  std::vector<uint32_t> lit_frames(stripes, 0);
  for (int f = 0; f < frames; ++f)
    for (int k = 0; k < stripes; ++k)
      if (layout.lights(f, k)) lit_frames[k] |= uint32_t{1} << f;
  return lit_frames;
}

// Fraction of a pixel lit by a frame: a box filter of the lit stripes over the pixel's stripe
// footprint [stripe - width/2, stripe + width/2], or the stripe under its centre if it is that
// narrow. The stripes and their overlaps are found once per pixel, then summed per frame.
class PixelCoverage {
 public:
  static constexpr int kMaxStripes = static_cast<int>(kMaxFootprint) + 2;
  PixelCoverage(float stripe, float width, const std::vector<uint32_t>& lit_frames)
      : width_(width) {
    const int stripes = static_cast<int>(lit_frames.size());
    if (std::isnan(stripe)) return;
    if (width < 1e-3f) {
      narrow_ = true;
      masks_[count_++] = lit_frames[std::clamp(static_cast<int>(stripe), 0, stripes - 1)];
      return;
    }
    const float lo = stripe - 0.5f * width, hi = stripe + 0.5f * width;
    for (int k = static_cast<int>(std::floor(lo)); k <= static_cast<int>(std::floor(hi)); ++k)
      if (k >= 0 && k < stripes) {
        if (count_ == kMaxStripes) throw std::logic_error("PixelCoverage: footprint too wide");
        masks_[count_] = lit_frames[k];
        overlaps_[count_++] = std::min(hi, k + 1.f) - std::max(lo, static_cast<float>(k));
      }
  }
  // Frames that light the same of the pixel's stripes have the same coverage: bit i of a
  // frame's pattern says whether it lights the pixel's i-th stripe.
  int stripeCount() const { return count_; }
  unsigned pattern(int frame) const {
    unsigned bits = 0;
    for (int i = 0; i < count_; ++i) bits |= ((masks_[i] >> frame) & 1u) << i;
    return bits;
  }
  float ofPattern(unsigned bits) const {
    if (narrow_) return static_cast<float>(bits & 1);
    float coverage = 0;
    for (int i = 0; i < count_; ++i) coverage += ((bits >> i) & 1) ? overlaps_[i] : 0.f;
    return count_ == 0 ? coverage : coverage / width_;
  }

 private:
  float width_;
  bool narrow_ = false;
  int count_ = 0;
  uint32_t masks_[kMaxStripes];
  float overlaps_[kMaxStripes];
};

// Blooming and stray light, in place: image = (1 - bloom) image + bloom G(image) + stray mean.
// The wide Gaussian runs on a copy downsampled to about half its sigma (it is smooth), so it
// costs a fraction of the lens blur below.
void applyBloom(const SensorModel& sensor, cv::Mat& image) {
  if (sensor.bloom_share <= 0 && sensor.stray_light <= 0) return;
  const cv::Scalar stray = cv::mean(image) * sensor.stray_light;
  if (sensor.bloom_share > 0 && sensor.bloom_sigma > 0) {
    const int factor = std::max(1, static_cast<int>(sensor.bloom_sigma / 2));
    cv::Mat small, halo;
    cv::resize(image, small,
               cv::Size((image.cols + factor - 1) / factor, (image.rows + factor - 1) / factor), 0,
               0, cv::INTER_AREA);
    const double sigma = sensor.bloom_sigma / factor;
    cv::GaussianBlur(small, small, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
    cv::resize(small, halo, image.size(), 0, 0, cv::INTER_LINEAR);
    cv::addWeighted(image, 1 - sensor.bloom_share, halo, sensor.bloom_share, 0, image);
  }
  if (sensor.stray_light > 0) cv::add(image, stray, image);
}

// The camera's optics: blooming and stray light, then a Gaussian blur of sensor.blur_sigma
// pixels, in place.
void applyOptics(const SensorModel& sensor, cv::Mat& image) {
  applyBloom(sensor, image);
  if (sensor.blur_sigma > 0)
    cv::GaussianBlur(image, image, cv::Size(0, 0), sensor.blur_sigma, sensor.blur_sigma,
                     cv::BORDER_REPLICATE);
}

// Sensor noise, then quantization to 8 bits. The samples come from the precomputed unit
// Gaussian table at an offset mixed from the seed, scan and image (stream), so that renders are
// deterministic and images differ. kShotNoise: the noise's sigma grows with the signal
// (SensorModel::shot_noise_gain); without it the flat-noise renders stay bit for bit as they were.
template <bool kShotNoise>
void addNoise(const cv::Mat& image, const SensorModel& sensor, const std::vector<float>& noise,
              uint32_t scan_id, uint64_t stream, cv::Mat& out) {
  size_t offset = mix(mix(sensor.seed) ^ mix(scan_id) ^ stream);
  const float sigma = static_cast<float>(sensor.noise_sigma);
  const float read_variance = sigma * sigma, gain = static_cast<float>(sensor.shot_noise_gain);
  out.create(image.size(), CV_MAKETYPE(CV_8U, image.channels()));
  const int values = image.cols * image.channels();
  for (int v = 0; v < image.rows; ++v) {
    const float* in = image.ptr<float>(v);
    uint8_t* o = out.ptr<uint8_t>(v);
    int i = 0;
#if CV_SIMD128
    // Same arithmetic as the scalar tail (no fused multiply-add, round to nearest even,
    // saturate), 16 values at a time over runs where the table does not wrap.
    const cv::v_float32x4 scale = cv::v_setall_f32(sigma), floor = cv::v_setall_f32(read_variance),
                          slope = cv::v_setall_f32(gain), zero = cv::v_setzero_f32();
    while (values - i >= 16) {
      const size_t start = offset & (kNoiseTableSize - 1);
      const int run = static_cast<int>(std::min<size_t>(values - i, kNoiseTableSize - start)) & ~15;
      if (run == 0) break;
      const float* n = noise.data() + start;
      for (int j = 0; j < run; j += 16) {
        cv::v_int32x4 q[4];
        for (int k = 0; k < 4; ++k) {
          const cv::v_float32x4 x = cv::v_load(in + i + j + 4 * k);
          const cv::v_float32x4 s =
              kShotNoise ? cv::v_sqrt(floor + slope * cv::v_max(x, zero)) : scale;
          q[k] = cv::v_round(x + s * cv::v_load(n + j + 4 * k));
        }
        cv::v_store(o + i + j, cv::v_pack_u(cv::v_pack(q[0], q[1]), cv::v_pack(q[2], q[3])));
      }
      i += run;
      offset += run;
    }
#endif
    for (; i < values; ++i) {
      const float s = kShotNoise ? std::sqrt(read_variance + gain * std::max(in[i], 0.f)) : sigma;
      o[i] = cv::saturate_cast<uint8_t>(in[i] + s * noise[offset++ & (kNoiseTableSize - 1)]);
    }
  }
}

void addNoise(const cv::Mat& image, const SensorModel& sensor, const std::vector<float>& noise,
              uint32_t scan_id, uint64_t stream, cv::Mat& out) {
  if (sensor.shot_noise_gain > 0)
    addNoise<true>(image, sensor, noise, scan_id, stream, out);
  else
    addNoise<false>(image, sensor, noise, scan_id, stream, out);
}

}  // namespace

SweptLaserProjector::MirrorFrame SweptLaserProjector::mirrorFrame() const {
  const Eigen::Vector3d axis = mirror_axis.normalized();
  const Eigen::Vector3d up(0, -1, 0);
  MirrorFrame frame;
  frame.e1 = (up - axis.dot(up) * axis).normalized();
  frame.e2 = frame.e1.cross(axis);
  frame.laser = laser_direction.normalized();
  frame.laser_from_axis = laser_origin - mirror_axis_point;
  return frame;
}

SweptLaserProjector::Plane SweptLaserProjector::planeAtAngle(double angle) const {
  return planeAtAngle(angle, mirrorFrame());
}

SweptLaserProjector::Plane SweptLaserProjector::planeAtAngle(double angle,
                                                             const MirrorFrame& frame) const {
  const Eigen::Vector3d mirror_normal = std::cos(angle) * frame.e1 + std::sin(angle) * frame.e2;
  const Eigen::Vector3d& d = frame.laser;
  // The laser meets the mirror face n . (x - axis_point) = offset: this point moves with angle.
  const double t =
      (mirror_offset - mirror_normal.dot(frame.laser_from_axis)) / mirror_normal.dot(d);
  Plane plane;
  plane.source = laser_origin + t * d;
  plane.central = d - 2 * d.dot(mirror_normal) * mirror_normal;
  Eigen::Vector3d spread = laser_fan_axis - 2 * laser_fan_axis.dot(mirror_normal) * mirror_normal;
  plane.spread = (spread - spread.dot(plane.central) * plane.central).normalized();
  plane.normal = plane.spread.cross(plane.central).normalized();
  plane.offset = -plane.normal.dot(plane.source);
  return plane;
}

VirtualPair::VirtualPair(VirtualPairConfig config, std::shared_ptr<const Scene> scene)
    : VirtualPair(std::move(config), std::move(scene), /*with_camera=*/true) {}

VirtualPair VirtualPair::projectorOnly(VirtualPairConfig config,
                                       std::shared_ptr<const Scene> scene) {
  return VirtualPair(std::move(config), std::move(scene), /*with_camera=*/false);
}

VirtualPair::VirtualPair(VirtualPairConfig config, std::shared_ptr<const Scene> scene,
                         bool with_camera)
    : config_(std::move(config)),
      scene_(std::move(scene)),
      layout_(config_.bits, config_.inverse_frames) {
  const PinholeCamera& camera = config_.camera;
  if (with_camera) {
    camera_rays_.reserve(static_cast<size_t>(camera.width) * camera.height);
    for (int v = 0; v < camera.height; ++v)
      for (int u = 0; u < camera.width; ++u) {
        const Eigen::Vector2d p = camera.normalizedPoint({u, v});
        camera_rays_.push_back(Eigen::Vector3d(p.x(), p.y(), 1.0).normalized().cast<float>());
      }
  }
  const int stripes = layout_.stripeCount();
  sweep_step_ = 1.0 / kSweepSamplesPerStripe;
  const SweptLaserProjector& projector = config_.projector;
  mirror_frame_ = projector.mirrorFrame();
  tan_fan_half_angle_ = std::tan(projector.fan_half_angle);
  for (int k = 0; k <= stripes * kSweepSamplesPerStripe; ++k) {
    const double fraction = k * sweep_step_ / stripes;
    const SweptLaserProjector::Plane plane = projector.planeAtAngle(
        projector.first_mirror_angle +
            fraction * (projector.last_mirror_angle - projector.first_mirror_angle),
        mirror_frame_);
    sweep_.push_back({plane.normal, plane.offset});
  }
  if (!with_camera) return;
  std::mt19937 generator(config_.sensor.seed);
  std::normal_distribution<float> normal(0.f, 1.f);
  noise_.resize(kNoiseTableSize);
  for (float& sample : noise_) sample = normal(generator);
}

double VirtualPair::trueStripe(const Eigen::Vector3d& point,
                               SweptLaserProjector::Plane* plane) const {
  auto side = [&](size_t k) { return sweep_[k].normal.dot(point) + sweep_[k].offset; };
  size_t lo = 0, hi = sweep_.size() - 1;
  double g_lo = side(lo), g_hi = side(hi);
  if (g_lo * g_hi > 0) return kNaN;  // outside the sweep
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    const double g_mid = side(mid);
    if ((g_mid > 0) == (g_lo > 0)) {
      lo = mid, g_lo = g_mid;
    } else {
      hi = mid, g_hi = g_mid;
    }
  }
  // Secant steps on the exact planes remove the table's interpolation error.
  const SweptLaserProjector& projector = config_.projector;
  const double stripes = layout_.stripeCount();
  const double slope = (g_hi - g_lo) / sweep_step_;
  double s = (lo + g_lo / (g_lo - g_hi)) * sweep_step_;
  for (int iteration = 0; iteration < 2; ++iteration) {
    *plane = projector.planeAtAngle(
        projector.first_mirror_angle +
            s / stripes * (projector.last_mirror_angle - projector.first_mirror_angle),
        mirror_frame_);
    s -= (plane->normal.dot(point) + plane->offset) / slope;
  }
  const Eigen::Vector3d to_point = point - plane->source;
  const double along = to_point.dot(plane->central);
  if (!(along > 0) || std::abs(to_point.dot(plane->spread)) > along * tan_fan_half_angle_)
    return kNaN;  // outside the laser fan
  return s;
}

// Another pair's light at one pixel (interference): its stripe and grey level there.
struct VirtualPair::ForeignLight {
  int u;
  float stripe;
  float level;
};

bool VirtualPair::lightAt(const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                          const Eigen::Vector3d& point_world, double albedo, float& stripe,
                          float& level) const {
  SweptLaserProjector::Plane plane;
  const double s = trueStripe(point, &plane);
  if (!std::isfinite(s)) return false;
  const Eigen::Vector3d to_source = plane.source - point;
  const double distance = to_source.norm();
  const double incidence = normal.dot(to_source) / distance;
  if (incidence <= 0 || scene_->occluded(point_world, config_.world_from_camera * plane.source))
    return false;
  stripe = static_cast<float>(s);
  level = static_cast<float>(config_.sensor.projector_level * albedo * incidence / distance);
  return true;
}

// What the camera sees at one pixel, before optics and noise.
struct VirtualPair::SurfaceSample {
  float stripe = std::numeric_limits<float>::quiet_NaN();
  float ambient_level = 0;    // grey level under ambient light alone
  float projector_level = 0;  // added where the projector lights the point
  cv::Vec3f color{0, 0, 0};
};

void VirtualPair::traceSurfaces(const std::vector<const VirtualPair*>& also_projecting,
                                GroundTruth& truth, std::vector<SurfaceSample>& samples,
                                std::vector<std::vector<ForeignLight>>& foreign) const {
  const PinholeCamera& camera = config_.camera;
  const SensorModel& sensor = config_.sensor;
  const int rows = camera.height, cols = camera.width;
  const Eigen::Isometry3d& pose = config_.world_from_camera;
  const Eigen::Matrix3d rotation = pose.linear();
  truth.points.create(rows, cols);
  truth.normals.create(rows, cols);
  truth.stripe.create(rows, cols);
  truth.surface.create(rows, cols);
  truth.skeleton = scene_->skeleton();

  cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& range) {
    // A row's rays at once (meshes cast them as packets).
    std::vector<Ray> rays(cols);
    std::vector<Hit> hits(cols);
    for (int v = range.start; v < range.end; ++v) {
      for (int u = 0; u < cols; ++u)
        rays[u] = Ray{pose.translation(),
                      rotation * camera_rays_[static_cast<size_t>(v) * cols + u].cast<double>()};
      scene_->intersectMany(rays.data(), cols, hits.data());
      for (int u = 0; u < cols; ++u) {
        const size_t index = static_cast<size_t>(v) * cols + u;
        const Eigen::Vector3d ray_camera = camera_rays_[index].cast<double>();
        const Hit& hit = hits[u];
        truth.surface(v, u) = -1;
        truth.points(v, u) = cv::Vec3f::all(std::numeric_limits<float>::quiet_NaN());
        truth.normals(v, u) = cv::Vec3f::all(std::numeric_limits<float>::quiet_NaN());
        truth.stripe(v, u) = std::numeric_limits<float>::quiet_NaN();
        if (!hit.surface) continue;
        const Eigen::Vector3d point_camera = hit.distance * ray_camera;
        const Eigen::Vector3d point_world = pose * point_camera;
        truth.surface(v, u) = hit.surface_index;
        truth.points(v, u) = toVec3f(point_camera);

        const Eigen::Vector3d normal_camera = rotation.transpose() * hit.normal;
        truth.normals(v, u) = toVec3f(normal_camera);
        double albedo = hit.surface->albedoAtHit(hit, point_world);
        Eigen::Vector3d color = hit.surface->colorAtHit(hit, point_world);
        if (hit.surface->patterned())
          averageOverPixel(*hit.surface, camera_rays_, rows, cols, pose, rotation, u, v, albedo,
                           color);
        SurfaceSample& sample = samples[index];
        sample.ambient_level = static_cast<float>(sensor.projector_level * albedo * sensor.ambient);
        const double facing = std::max(0.0, -normal_camera.dot(ray_camera));
        sample.color = toVec3f(color) * static_cast<float>(255.0 * (0.3 + 0.7 * facing));

        for (const VirtualPair* other : also_projecting) {
          float stripe, level;
          const Eigen::Isometry3d& other_pose = other->config_.world_from_camera;
          if (other != this && other->lightAt(other_pose.inverse() * point_world,
                                              other_pose.linear().transpose() * hit.normal,
                                              point_world, albedo, stripe, level))
            foreign[v].push_back({u, stripe, level});
        }
        if (!lightAt(point_camera, normal_camera, point_world, albedo, sample.stripe,
                     sample.projector_level))
          continue;
        truth.stripe(v, u) = sample.stripe;
      }
    }
  });
}

std::vector<float> VirtualPair::stripeFootprints(const std::vector<SurfaceSample>& samples,
                                                 int rows, int cols, double line_width) {
  const float line = static_cast<float>(line_width);
  std::vector<float> footprint(samples.size(), 0.f);
  auto stripe_at = [&](int v, int u) {
    return (u < 0 || v < 0 || u >= cols || v >= rows)
               ? std::numeric_limits<float>::quiet_NaN()
               : samples[static_cast<size_t>(v) * cols + u].stripe;
  };
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      const float s = stripe_at(v, u);
      if (std::isnan(s)) continue;
      const float du = smallerStep(s, stripe_at(v, u - 1), stripe_at(v, u + 1));
      const float dv = smallerStep(s, stripe_at(v - 1, u), stripe_at(v + 1, u));
      // Two box filters in a row as one box of their summed variance.
      const float camera = std::hypot(du, dv);
      footprint[static_cast<size_t>(v) * cols + u] =
          std::min(line > 0 ? std::hypot(camera, line) : camera, kMaxFootprint);
    }
  return footprint;
}

void VirtualPair::shadeFrames(const std::vector<uint32_t>& lit_frames,
                              const std::vector<SurfaceSample>& samples,
                              const std::vector<float>& footprint,
                              const std::vector<std::vector<ForeignLight>>& foreign, int row_begin,
                              int row_end, std::vector<cv::Mat1f>& images) const {
  const int cols = images[0].cols, frames = static_cast<int>(images.size());
  const int stripes = static_cast<int>(lit_frames.size());
  std::vector<float*> out(frames);
  float levels[1 << PixelCoverage::kMaxStripes];
  for (int v = row_begin; v < row_end; ++v) {
    for (int f = 0; f < frames; ++f) out[f] = images[f].ptr<float>(v);
    const ForeignLight* light = foreign.empty() ? nullptr : foreign[v].data();
    const ForeignLight* lights_end = foreign.empty() ? nullptr : light + foreign[v].size();
    for (int u = 0; u < cols; ++u) {
      const size_t index = static_cast<size_t>(v) * cols + u;
      const SurfaceSample& sample = samples[index];
      const PixelCoverage coverage(sample.stripe, footprint[index], lit_frames);
      // Each distinct grey level once (a pixel spans at most a few stripes), then per frame.
      const unsigned patterns = 1u << coverage.stripeCount();
      for (unsigned bits = 0; bits < patterns; ++bits)
        levels[bits] = sample.ambient_level + sample.projector_level * coverage.ofPattern(bits);
      for (int f = 0; f < frames; ++f) out[f][u] = levels[coverage.pattern(f)];
      // Other pairs' stripes, point-sampled (they only need to corrupt, not to decode).
      for (; light != lights_end && light->u == u; ++light) {
        const uint32_t lit =
            lit_frames[std::clamp(static_cast<int>(light->stripe), 0, stripes - 1)];
        for (int f = 0; f < frames; ++f)
          out[f][u] += light->level * static_cast<float>((lit >> f) & 1);
      }
    }
  }
}

RenderedPatternSet VirtualPair::render(
    uint32_t scan_id, const std::vector<const VirtualPair*>& also_projecting) const {
  if (camera_rays_.empty())
    throw std::logic_error("VirtualPair::render on a projector-only pair (" + config_.pair_id +
                           ")");
  const SensorModel& sensor = config_.sensor;
  const int rows = config_.camera.height, cols = config_.camera.width;
  RenderedPatternSet result;
  // What each pixel sees (shared by all frames), and the other pairs' light on it.
  // Per-render scratch is kept per calling thread: fresh pages for tens of MB per render cost
  // more than the shading itself. (Named by references: the parallel loops below run on other
  // threads, where a thread_local name would mean their own copy.)
  thread_local std::vector<SurfaceSample> samples_scratch;
  thread_local std::vector<cv::Mat1f> images_scratch;
  std::vector<SurfaceSample>& samples = samples_scratch;
  std::vector<cv::Mat1f>& images = images_scratch;
  samples.assign(static_cast<size_t>(rows) * cols, SurfaceSample{});
  std::vector<std::vector<ForeignLight>> foreign(also_projecting.empty() ? 0 : rows);
  traceSurfaces(also_projecting, result.truth, samples, foreign);
  // Stripe footprint of each pixel: how much of the coordinate its area spans (antialiasing
  // keeps the subpixel position of stripe edges in the image, as a real sensor does).
  const std::vector<float> footprint =
      stripeFootprints(samples, rows, cols, config_.projector.line_width);
  const std::vector<uint32_t> lit_frames = framesLighting(layout_);

  const int frames = layout_.frameCount();
  images.resize(frames);
  for (cv::Mat1f& image : images) image.create(rows, cols);
  cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& range) {
    shadeFrames(lit_frames, samples, footprint, foreign, range.start, range.end, images);
  });
  result.frames.resize(frames);
  cv::parallel_for_(cv::Range(0, frames), [&](const cv::Range& range) {
    for (int f = range.start; f < range.end; ++f) {
      applyOptics(sensor, images[f]);
      addNoise(images[f], sensor, noise_, scan_id, static_cast<uint64_t>(f) + 1, result.frames[f]);
    }
  });

  cv::Mat3f texture(rows, cols);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) texture(v, u) = samples[static_cast<size_t>(v) * cols + u].color;
  applyOptics(sensor, texture);
  addNoise(texture, sensor, noise_, scan_id, 0, result.texture);
  return result;
}

VirtualPairConfig withRealCaptureOptics(VirtualPairConfig config, const RealCaptureOptics& optics) {
  if (config.projector.line_width == 0) config.projector.line_width = optics.line_width;
  SensorModel& sensor = config.sensor;
  if (sensor.bloom_share == 0) {
    sensor.bloom_share = optics.bloom_share;
    sensor.bloom_sigma = optics.bloom_sigma;
  }
  if (sensor.stray_light == 0) sensor.stray_light = optics.stray_light;
  if (sensor.shot_noise_gain == 0) {
    sensor.noise_sigma = optics.noise_sigma;
    sensor.shot_noise_gain = optics.shot_noise_gain;
  }
  return config;
}

PairCalibration VirtualPair::factoryCalibration() const {
  PairCalibration calibration;
  calibration.pair_id = config_.pair_id;
  calibration.source = "factory (simulator ground truth)";
  calibration.camera = config_.camera;
  const SweptLaserProjector& projector = config_.projector;
  const int stripes = layout_.stripeCount();
  for (int i = 0; i < stripes; ++i) {
    const SweptLaserProjector::Plane plane = projector.planeAtAngle(
        projector.first_mirror_angle +
        (i + 0.5) / stripes * (projector.last_mirror_angle - projector.first_mirror_angle));
    calibration.projector.planes.emplace_back(plane.normal.x(), plane.normal.y(), plane.normal.z(),
                                              plane.offset);
  }
  return calibration;
}

}  // namespace body_scan_driver::sim
