// Nearest-neighbour identification of thesis 5.7 (eq 5.16): a probe's normalized feature
// vector phi_U against every gallery pose phi_{m,n}; the answer is the subject m, the pose n and
// the score E_r = min ||phi_U - phi_{m,n}|| (L2).
//
// The search is exact (the same nearest pose as a brute-force scan) but indexed so that a query
// stays fast on large galleries: the normalized vectors are rotated onto their principal axes
// (an orthogonal map, so L2 distances do not change) and stored as contiguous float32 rows in
// the leaf order of a k-d tree (median splits on the axis of largest spread, leaves of <= 64
// rows). A query descends to its own leaf first, then visits a far cell only if the squared
// distance from the query to that cell's box (kept incrementally, Arya & Mount) can still beat
// the best; each candidate's distance is summed highest-variance axes first, 8 at a time, and
// abandoned as soon as it exceeds the best (partial-distance early exit). Gait features are
// strongly correlated, so the leading axes carry most of the spread and the boxes prune well
// although phi has 22-34 dimensions. Scores carry float32 rounding (~1e-6 relative).
#pragma once

#include <body_gait_id/gait_features.h>

#include <cstdint>
#include <vector>

namespace body_gait_id {

struct GalleryPose {
  std::int64_t subject_id;
  int sequence;  // training sequence (e.g. 0 = eta1, 1 = eta2)
  int frame;     // pose index in the sequence (1-based gait-cycle frame)
  GaitFeatures features;
};

struct Match {
  std::int64_t subject_id;
  int sequence;
  int frame;
  double score;  // eq 5.16: L2 distance of the normalized feature vectors
};

class Matcher {
 public:
  // Fits the normalization (eqs 5.14-5.15) to the gallery. Throws std::invalid_argument for an
  // empty gallery or features of mixed sizes.
  Matcher(std::vector<GalleryPose> gallery, FeatureSet set);
  // Uses statistics stored with the gallery (database), so identification does not drift when
  // the statistics are not refitted.
  Matcher(std::vector<GalleryPose> gallery, FeatureSet set, FeatureNormalization stored);

  // Nearest gallery pose (eq 5.16). Throws std::invalid_argument when the probe's sizes do not
  // match the gallery's (another view).
  Match identify(const GaitFeatures& probe) const;
  // The best match of every enrolled subject, best first (CMC, ROC, open-set threshold).
  std::vector<Match> rankSubjects(const GaitFeatures& probe) const;

  const FeatureNormalization& normalization() const { return normalization_; }
  FeatureSet featureSet() const { return set_; }
  std::size_t size() const { return ids_.size(); }

 private:
  void build(std::vector<GalleryPose> gallery);
  // The probe's row in the principal-axes frame (padded to stride_ floats).
  std::vector<float> project(const GaitFeatures& probe) const;
  const float* row(std::size_t i) const { return rows_.data() + i * stride_; }
  struct Search;
  void search(int node, float cell_distance, Search& s) const;

  FeatureSet set_;
  FeatureNormalization normalization_;
  int dimension_ = 0;  // length of phi
  int stride_ = 0;     // dimension_ rounded up to a multiple of 8 (zero padded)
  Eigen::VectorXf centre_;
  Eigen::MatrixXf axes_;     // columns: principal axes, highest variance first
  std::vector<float> rows_;  // in the tree's leaf order
  struct Node {
    int axis = -1;    // split axis, -1 for a leaf
    float split = 0;  // rows below go left, the others right
    int left = -1, right = -1;
    std::uint32_t begin = 0, end = 0;  // a leaf's rows
  };
  std::vector<Node> nodes_;  // nodes_[0] is the root
  struct PoseId {
    std::int64_t subject_id;
    int sequence, frame;
    std::uint32_t gallery_index;  // position in the constructor's gallery (ties: lowest wins)
    std::uint32_t subject_slot;   // dense subject index for rankSubjects
  };
  std::vector<PoseId> ids_;
  std::size_t subject_count_ = 0;
};

// The named peer: eq 5.16 as written, a brute-force scan in double precision over the
// normalized gallery (one column per pose). Ties go to the lowest gallery index. Tests and the
// benchmark compare the indexed Matcher with it.
class BruteForceMatcher {
 public:
  BruteForceMatcher(const std::vector<GalleryPose>& gallery, FeatureSet set,
                    FeatureNormalization normalization);
  Match identify(const GaitFeatures& probe) const;

 private:
  FeatureSet set_;
  FeatureNormalization normalization_;
  Eigen::MatrixXd phi_;
  std::vector<GalleryPose> ids_;  // features left empty
};

}  // namespace body_gait_id
