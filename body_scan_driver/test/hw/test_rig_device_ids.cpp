// The `device:` map of a rig file's pairs (hw/rig_device_ids.h): read for the asked pair,
// empty without a map, and every mistake named.
#include <body_scan_driver/hw/rig_device_ids.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace body_scan_driver::hw {
namespace {

std::string writeRig(const std::string& pairs_of_pole_a) {
  const std::string path = testing::TempDir() + "/rig_device_ids_test.yaml";
  std::ofstream(path) << "name: test\npoles:\n  - name: pole_a\n    position: [1, 0]\n"
                      << "    pairs:\n"
                      << pairs_of_pole_a;
  return path;
}

std::string errorOf(const std::string& path, const std::string& pair_id) {
  try {
    loadPairDeviceIds(path, pair_id);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(RigDeviceIds, ReadsThePairsMapAndNothingForAPairWithout) {
  const std::string path = writeRig(
      "      - {name: pair_1, height: 1.8, device: {camera_id: \"046d:0825\", camera_serial: "
      "A1, projector_id: \"1234:abcd\", projector_serial: P1, projector_display: \":1\", "
      "projector_screen: 2}}\n"
      "      - {name: pair_2, height: 1.1}\n");
  const PairDeviceIds first = loadPairDeviceIds(path, "pole_a/pair_1");
  EXPECT_EQ(first.camera_id, "046d:0825");
  EXPECT_EQ(first.camera_serial, "A1");
  EXPECT_EQ(first.projector_id, "1234:abcd");
  EXPECT_EQ(first.projector_serial, "P1");
  EXPECT_EQ(first.projector_display, ":1");
  EXPECT_EQ(first.projector_screen, 2);
  const PairDeviceIds second = loadPairDeviceIds(path, "pole_a/pair_2");
  EXPECT_FALSE(second.camera_id || second.camera_serial || second.projector_id ||
               second.projector_serial || second.projector_display || second.projector_screen);
}

TEST(RigDeviceIds, NamesAnUnknownPairAKeyTypoAWrongTypeAndAMissingFile) {
  const std::string path = writeRig(
      "      - {name: pair_1, height: 1.8, device: {camera_serial: A1, projector_screen: one}}\n"
      "      - {name: pair_2, height: 1.1, device: {camera_ids: \"046d:0825\"}}\n");
  const std::string unknown_pair = errorOf(path, "pole_b/pair_1");
  EXPECT_NE(unknown_pair.find("'pole_b/pair_1' is not in rig file"), std::string::npos)
      << unknown_pair;
  EXPECT_NE(unknown_pair.find("pole_a/pair_1, pole_a/pair_2"), std::string::npos) << unknown_pair;
  const std::string typo = errorOf(path, "pole_a/pair_2");
  EXPECT_NE(typo.find("pair pole_a/pair_2, device: unknown key 'camera_ids'"), std::string::npos)
      << typo;
  EXPECT_NE(typo.find("camera_id, camera_serial"), std::string::npos) << typo;
  const std::string type = errorOf(path, "pole_a/pair_1");
  EXPECT_NE(type.find("'projector_screen' has the wrong type"), std::string::npos) << type;
  const std::string missing = errorOf(path + ".absent", "pole_a/pair_1");
  EXPECT_NE(missing.find("cannot read rig file"), std::string::npos) << missing;
}

}  // namespace
}  // namespace body_scan_driver::hw
