#include <body_scan_merge/ply_writer.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

TEST(PlyWriter, WritesFinitePointsWithColourAndAHeaderThatCountsThem) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  float rgb;
  const uint32_t packed = 0x10A0F0;
  std::memcpy(&rgb, &packed, sizeof rgb);
  const std::vector<float> cloud = {0.1f, 0.2f, 1.0f,  rgb,   nan,  nan,
                                    nan,  rgb,  -0.5f, 0.25f, 2.0f, rgb};
  const std::string path = std::filesystem::temp_directory_path() /
                           ("body_scan_test_cloud_" + std::to_string(::getpid()) + ".ply");
  ASSERT_EQ(body_scan_merge::writePly(path, cloud.data(), 3, 4, 3), 2u);

  std::ifstream file(path, std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(file)),
                            std::istreambuf_iterator<char>());
  const std::string end = "end_header\n";
  const size_t body = content.find(end) + end.size();
  EXPECT_NE(content.find("element vertex 2\n"), std::string::npos);
  ASSERT_EQ(content.size() - body, 2u * 15u);  // two vertices of 3 floats + 3 bytes
  float xyz[3];
  std::memcpy(xyz, content.data() + body + 15, sizeof xyz);
  EXPECT_FLOAT_EQ(xyz[0], -0.5f);
  EXPECT_FLOAT_EQ(xyz[2], 2.0f);
  EXPECT_EQ(static_cast<uint8_t>(content[body + 12]), 0x10);  // red
  EXPECT_EQ(static_cast<uint8_t>(content[body + 14]), 0xF0);  // blue
  // And back.
  const std::vector<float> read = body_scan_merge::readPly(path);
  ASSERT_EQ(read.size(), 8u);
  EXPECT_FLOAT_EQ(read[4], -0.5f);
  EXPECT_FLOAT_EQ(read[6], 2.0f);
  uint32_t rgb_read;
  std::memcpy(&rgb_read, &read[7], sizeof rgb_read);
  EXPECT_EQ(rgb_read, packed);
  std::ofstream(path, std::ios::app) << "x";  // trailing bytes are fine; a short file is not
  std::filesystem::resize_file(path, content.size() - 1);
  EXPECT_THROW(body_scan_merge::readPly(path), std::runtime_error);
  std::filesystem::remove(path);
}

TEST(PcdWriter, WritesABinaryPcdWithTheFinitePointsAndTheirPackedColour) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  float rgb;
  const uint32_t packed = 0x10A0F0;
  std::memcpy(&rgb, &packed, sizeof rgb);
  const std::vector<float> cloud = {0.1f, 0.2f, 1.0f, rgb, nan, 0, 0, rgb, -0.5f, 0.25f, 2.0f, rgb};
  const std::string path = std::filesystem::temp_directory_path() /
                           ("body_scan_test_cloud_" + std::to_string(::getpid()) + ".pcd");
  ASSERT_EQ(body_scan_merge::writePcd(path, cloud.data(), 3, 4, 3), 2u);

  std::ifstream file(path, std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(file)),
                            std::istreambuf_iterator<char>());
  const std::string end = "DATA binary\n";
  const size_t body = content.find(end) + end.size();
  for (const char* line : {"FIELDS x y z rgb\n", "WIDTH 2\n", "HEIGHT 1\n", "POINTS 2\n"})
    EXPECT_NE(content.find(line), std::string::npos) << line;
  ASSERT_EQ(content.size() - body, 2u * 16u);
  float point[4];
  std::memcpy(point, content.data() + body + 16, sizeof point);
  EXPECT_FLOAT_EQ(point[0], -0.5f);
  EXPECT_FLOAT_EQ(point[1], 0.25f);
  uint32_t colour;
  std::memcpy(&colour, &point[3], sizeof colour);
  EXPECT_EQ(colour, packed);
  std::filesystem::remove(path);
}

TEST(PlyWriter, UnwritablePathNamesThePath) {
  const float point[3] = {0, 0, 1};
  try {
    body_scan_merge::writePly("/proc/body_scan_forbidden/cloud.ply", point, 1, 3, -1);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("body_scan_forbidden"), std::string::npos) << e.what();
  }
}
