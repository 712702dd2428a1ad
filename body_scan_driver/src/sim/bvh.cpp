// Strict BVH reader: a tokenizer that remembers line numbers, a recursive-descent parser of the
// hierarchy (depth-limited, so hostile input cannot overflow the stack) and a line-based reader
// of the motion block (one frame per line).
#include <body_scan_driver/sim/bvh.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace body_scan_driver::sim {

BvhError::BvhError(const std::string& source, int line, const std::string& problem)
    : std::runtime_error(source + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
                         problem),
      line_(line) {}

int BvhMotion::jointIndex(const std::string& name) const {
  for (size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == name) return static_cast<int>(i);
  return -1;
}

namespace {

constexpr int kMaxDepth = 256;  // deeper trees are hostile input, not bodies
constexpr int kMaxJoints = 10000;
constexpr long kMaxFrames = 10000000;  // ~23 h at 120 fps

struct Token {
  std::string text;
  int line;
};

std::vector<Token> tokenize(const std::string& text) {
  std::vector<Token> tokens;
  int line = 1;
  size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++i;
    } else if (c == '{' || c == '}') {
      tokens.push_back({std::string(1, c), line});
      ++i;
    } else {
      const size_t start = i;
      while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])) &&
             text[i] != '{' && text[i] != '}')
        ++i;
      tokens.push_back({text.substr(start, i - start), line});
    }
  }
  return tokens;
}

class Parser {
 public:
  Parser(const std::string& text, const std::string& source)
      : source_(source), tokens_(tokenize(text)) {}

  BvhMotion parse() {
    expectKeyword("HIERARCHY", "a BVH file starts with HIERARCHY");
    const Token& root = next("ROOT");
    if (root.text != "ROOT")
      fail(root.line, "expected ROOT, got '" + root.text + "' (the hierarchy has one ROOT joint)");
    parseJoint(-1, 0);
    const Token& motion = next("MOTION");
    if (motion.text == "ROOT")
      fail(motion.line, "a second ROOT: only files with one skeleton are supported");
    if (motion.text != "MOTION")
      fail(motion.line,
           "expected MOTION or a closing '}' count that matches, got '" + motion.text + "'");
    parseMotion();
    return std::move(motion_);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw BvhError(source_, line, problem);
  }
  int lastLine() const { return tokens_.empty() ? 1 : tokens_.back().line; }

  const Token& next(const std::string& expected) {
    if (at_ >= tokens_.size())
      fail(lastLine(), "unexpected end of file, expected " + expected + " (the file is truncated)");
    return tokens_[at_++];
  }
  void expectKeyword(const std::string& keyword, const std::string& why) {
    const Token& token = next(keyword);
    if (token.text != keyword)
      fail(token.line, "expected " + keyword + ", got '" + token.text + "' (" + why + ")");
  }
  double number(const Token& token, const std::string& what) const {
    const char* begin = token.text.data();
    const char* end = begin + token.text.size();
    if (begin != end && *begin == '+') ++begin;
    double value = 0;
    const auto result = std::from_chars(begin, end, value);
    if (result.ec != std::errc() || result.ptr != end || begin == end)
      fail(token.line, what + " must be a number, got '" + token.text + "'");
    if (!std::isfinite(value))
      fail(token.line, what + " must be finite, got '" + token.text + "' (no NaN or infinity)");
    return value;
  }
  Eigen::Vector3d offset(const std::string& joint) {
    expectKeyword("OFFSET", "each joint and end site starts with OFFSET x y z");
    Eigen::Vector3d value;
    for (int axis = 0; axis < 3; ++axis)
      value[axis] = number(next("an OFFSET value"), "OFFSET of '" + joint + "'");
    return value;
  }

  void parseJoint(int parent, int depth) {
    if (depth > kMaxDepth)
      fail(tokens_[at_ - 1].line,
           "the hierarchy is deeper than " + std::to_string(kMaxDepth) + " joints");
    if (int(motion_.joints.size()) >= kMaxJoints)
      fail(tokens_[at_ - 1].line, "more than " + std::to_string(kMaxJoints) + " joints");
    const Token& name = next("a joint name");
    if (name.text == "{") fail(name.line, "a joint needs a name before '{'");
    if (motion_.jointIndex(name.text) >= 0)
      fail(name.line, "joint '" + name.text + "' appears twice (joint names must be unique)");
    const int index = static_cast<int>(motion_.joints.size());
    motion_.joints.push_back({});
    motion_.joints[index].name = name.text;
    motion_.joints[index].parent = parent;
    expectKeyword("{", "a joint's block opens with '{'");
    motion_.joints[index].offset = offset(name.text);
    parseChannels(index);
    bool end_site = false;
    for (;;) {
      const Token& token = next("JOINT, End Site or '}'");
      if (token.text == "}") break;
      if (token.text == "JOINT") {
        parseJoint(index, depth + 1);
      } else if (token.text == "End") {
        const Token& site = next("Site");
        if (site.text != "Site")
          fail(site.line, "expected 'End Site', got 'End " + site.text + "'");
        if (end_site) fail(site.line, "joint '" + name.text + "' has two End Sites");
        end_site = true;
        expectKeyword("{", "an End Site block opens with '{'");
        motion_.joints[index].has_end_site = true;
        motion_.joints[index].end_site = offset(name.text + " End Site");
        expectKeyword("}", "an End Site holds only its OFFSET");
      } else {
        fail(token.line, "unknown keyword '" + token.text + "' in joint '" + name.text +
                             "' (expected JOINT, End Site or '}')");
      }
    }
  }

  void parseChannels(int index) {
    const Token& keyword = next("CHANNELS");
    if (keyword.text != "CHANNELS")
      fail(keyword.line, "expected CHANNELS after the OFFSET of '" + motion_.joints[index].name +
                             "', got '" + keyword.text + "'");
    const Token& count_token = next("the channel count");
    const double count = number(count_token, "the channel count");
    if (count != std::floor(count) || count < 0 || count > 6)
      fail(count_token.line,
           "the channel count must be an integer 0..6, got '" + count_token.text + "'");
    static const std::pair<const char*, BvhChannel> kNames[] = {
        {"Xposition", BvhChannel::kXposition}, {"Yposition", BvhChannel::kYposition},
        {"Zposition", BvhChannel::kZposition}, {"Xrotation", BvhChannel::kXrotation},
        {"Yrotation", BvhChannel::kYrotation}, {"Zrotation", BvhChannel::kZrotation}};
    BvhJoint& joint = motion_.joints[index];
    joint.first_channel = motion_.channel_count;
    for (int i = 0; i < int(count); ++i) {
      const Token& token = next("a channel name");
      bool known = false;
      for (const auto& [text, channel] : kNames) {
        if (token.text != text) continue;
        for (BvhChannel seen : joint.channels)
          if (seen == channel)
            fail(token.line, "channel '" + token.text + "' appears twice in '" + joint.name + "'");
        joint.channels.push_back(channel);
        known = true;
      }
      if (!known)
        fail(token.line, "unknown channel '" + token.text + "' in '" + joint.name + "' (expected " +
                             std::to_string(int(count)) +
                             " of Xposition Yposition Zposition Xrotation Yrotation Zrotation)");
    }
    motion_.channel_count += int(count);
  }

  void parseMotion() {
    const Token& frames_keyword = next("Frames:");
    if (frames_keyword.text != "Frames:")
      fail(frames_keyword.line,
           "expected 'Frames: N' after MOTION, got '" + frames_keyword.text + "'");
    const Token& frames_token = next("the frame count");
    const double frames = number(frames_token, "the frame count");
    if (frames != std::floor(frames) || frames < 1 || frames > kMaxFrames)
      fail(frames_token.line, "the frame count must be an integer 1.." +
                                  std::to_string(kMaxFrames) + ", got '" + frames_token.text + "'");
    const Token& frame_keyword = next("Frame Time:");
    const Token& time_keyword = next("Frame Time:");
    if (frame_keyword.text != "Frame" || time_keyword.text != "Time:")
      fail(frame_keyword.line, "expected 'Frame Time: SECONDS' after the frame count, got '" +
                                   frame_keyword.text + " " + time_keyword.text + "'");
    const Token& time_token = next("the frame time");
    motion_.frame_time = number(time_token, "the frame time");
    if (!(motion_.frame_time > 0))
      fail(time_token.line, "the frame time must be > 0 s, got '" + time_token.text + "'");
    const int header_line = time_token.line;

    // One frame per line, exactly channel_count values each.
    const long expected = long(frames);
    std::vector<double> values;
    while (at_ < tokens_.size()) {
      const int line = tokens_[at_].line;
      if (line == header_line)
        fail(line, "frame values must start on the line after 'Frame Time:'");
      if (long(motion_.frames.size()) == expected)
        fail(line, "more frame lines than 'Frames: " + std::to_string(expected) +
                       "' (fix the count or remove the extra lines)");
      values.clear();
      for (; at_ < tokens_.size() && tokens_[at_].line == line; ++at_)
        values.push_back(number(tokens_[at_], "frame " + std::to_string(motion_.frames.size() + 1) +
                                                  " value " + std::to_string(values.size() + 1)));
      if (int(values.size()) != motion_.channel_count)
        fail(line, "frame " + std::to_string(motion_.frames.size() + 1) + " has " +
                       std::to_string(values.size()) + " values, the hierarchy declares " +
                       std::to_string(motion_.channel_count) + " channels");
      motion_.frames.push_back(values);
    }
    if (long(motion_.frames.size()) != expected)
      fail(lastLine(), "'Frames: " + std::to_string(expected) + "' but only " +
                           std::to_string(motion_.frames.size()) +
                           " frame lines (the file is truncated or the count is wrong)");
  }

  std::string source_;
  std::vector<Token> tokens_;
  size_t at_ = 0;
  BvhMotion motion_;
};

Eigen::Matrix3d channelRotation(BvhChannel channel, double degrees) {
  const double angle = degrees * M_PI / 180.0;
  switch (channel) {
    case BvhChannel::kXrotation:
      return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
    case BvhChannel::kYrotation:
      return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
    case BvhChannel::kZrotation:
      return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    default:
      return Eigen::Matrix3d::Identity();
  }
}

}  // namespace

BvhMotion parseBvh(const std::string& text, const std::string& source) {
  return Parser(text, source).parse();
}

BvhMotion loadBvh(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw BvhError(path, 0, "cannot open the file (check the path and permissions)");
  std::ostringstream text;
  text << file.rdbuf();
  return parseBvh(text.str(), path);
}

BvhPose poseBvhFrame(const BvhMotion& motion, int frame) {
  if (frame < 0 || frame >= int(motion.frames.size()))
    throw std::out_of_range("BVH frame " + std::to_string(frame) + " outside 0.." +
                            std::to_string(int(motion.frames.size()) - 1));
  const std::vector<double>& values = motion.frames[frame];
  const size_t count = motion.joints.size();
  BvhPose pose;
  pose.position.resize(count);
  pose.rotation.resize(count);
  pose.end_site.resize(count);
  for (size_t j = 0; j < count; ++j) {
    const BvhJoint& joint = motion.joints[j];
    Eigen::Vector3d translation = joint.offset;
    Eigen::Matrix3d local = Eigen::Matrix3d::Identity();
    for (size_t c = 0; c < joint.channels.size(); ++c) {
      const double value = values[joint.first_channel + c];
      switch (joint.channels[c]) {
        case BvhChannel::kXposition:
          translation.x() += value;
          break;
        case BvhChannel::kYposition:
          translation.y() += value;
          break;
        case BvhChannel::kZposition:
          translation.z() += value;
          break;
        default:
          local = local * channelRotation(joint.channels[c], value);
      }
    }
    if (joint.parent < 0) {
      pose.position[j] = translation;
      pose.rotation[j] = local;
    } else {
      pose.position[j] = pose.position[joint.parent] + pose.rotation[joint.parent] * translation;
      pose.rotation[j] = pose.rotation[joint.parent] * local;
    }
    pose.end_site[j] = pose.position[j] + pose.rotation[j] * joint.end_site;
  }
  return pose;
}

}  // namespace body_scan_driver::sim
