// Where the simulator's data are at run time, for tests and evaluation: body_scan_driver's
// folder as rospack finds it (source or install space), never a source path compiled in.
// Header-only, so that the simulator library stays free of ROS: whoever includes it links roslib.
#pragma once

#include <body_scan_driver/sim/mesh_human.h>
#include <body_scan_driver/tools/package_file.h>

#include <cstdlib>
#include <string>

namespace body_scan_driver::sim {

// body_scan_driver's package folder (config/, data/). Throws std::runtime_error when rospack
// cannot find it.
inline std::string driverPackageDir() { return tools::packageDir("body_scan_driver"); }

// Pair files, scenes, rigs and the BVH joint map.
inline std::string driverConfigDir() { return driverPackageDir() + "/config"; }

// The CMU walks (data/cmu_walks/README.md: license, acknowledgement). BODY_SCAN_BVH_DIR, when
// set, names another folder with the same file names.
inline std::string cmuWalksDir() {
  if (const char* dir = std::getenv("BODY_SCAN_BVH_DIR")) return dir;
  return driverPackageDir() + "/data/cmu_walks";
}

// The mesh human's body kit (data/mesh_human/README.md: license, attribution) and retarget map.
inline MeshHumanFiles meshHumanFiles() {
  return {driverPackageDir() + "/data/mesh_human/mesh_human.bin",
          driverConfigDir() + "/mesh/mesh_retarget.yaml"};
}

}  // namespace body_scan_driver::sim
