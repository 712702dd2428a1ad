#include <body_scan_driver/sim/scene.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace body_scan_driver::sim;

namespace {

Ray along(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  return Ray{origin, direction.normalized()};
}

}  // namespace

TEST(Scene, PrimitivesAreHitWhereGeometrySaysWithOutwardNormals) {
  Hit hit;
  const Sphere sphere({2, 0, 0}, 0.5, Material{});
  ASSERT_TRUE(sphere.intersect(along({0, 0, 0}, {1, 0, 0}), 1e-9, 10, hit));
  EXPECT_NEAR(hit.distance, 1.5, 1e-12);
  EXPECT_NEAR(hit.normal.x(), -1, 1e-12);

  const Ellipsoid ellipsoid({0, 0, 1}, Eigen::Matrix3d::Identity(), {0.1, 0.2, 0.3}, Material{});
  ASSERT_TRUE(ellipsoid.intersect(along({0, 0, 3}, {0, 0, -1}), 1e-9, 10, hit));
  EXPECT_NEAR(hit.distance, 3 - 1.3, 1e-12);  // top of the 0.3 semi-axis
  EXPECT_NEAR(hit.normal.z(), 1, 1e-12);
  ASSERT_TRUE(ellipsoid.intersect(along({-1, 0, 1}, {1, 0, 0}), 1e-9, 10, hit));
  EXPECT_NEAR(hit.distance, 0.9, 1e-12);

  const Cylinder cylinder({0, 0, 0}, {0, 0, 1}, 0.2, 1.0, Material{});
  ASSERT_TRUE(cylinder.intersect(along({1, 0, 0.5}, {-1, 0, 0}), 1e-9, 10, hit));  // side
  EXPECT_NEAR(hit.distance, 0.8, 1e-12);
  EXPECT_NEAR(hit.normal.x(), 1, 1e-12);
  ASSERT_TRUE(cylinder.intersect(along({0.1, 0, 2}, {0, 0, -1}), 1e-9, 10, hit));  // top cap
  EXPECT_NEAR(hit.distance, 1.0, 1e-12);
  EXPECT_NEAR(hit.normal.z(), 1, 1e-12);
  EXPECT_FALSE(cylinder.intersect(along({1, 0, 1.5}, {-1, 0, 0}), 1e-9, 10, hit));  // above it

  const Plane bounded({0, 0, 0}, {0, 0, 1}, Material{}, 0.5);
  EXPECT_TRUE(bounded.intersect(along({0.4, 0.4, 1}, {0, 0, -1}), 1e-9, 10, hit));
  EXPECT_FALSE(bounded.intersect(along({0.6, 0, 1}, {0, 0, -1}), 1e-9, 10, hit));
}

TEST(Scene, CheckerboardAlternatesAlbedoPerSquare) {
  // 4 x 3 squares of 30 mm facing -x, centred at x = 1.
  const CheckerboardPlane board({1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, 4, 3, 0.03, 0.8, 0.1);
  Hit hit;
  ASSERT_TRUE(board.intersect(along({0, 0.015, 0.0}, {1, 0, 0}), 1e-9, 10, hit));
  EXPECT_NEAR(hit.distance, 1.0, 1e-12);
  const double first = board.albedoAt({1, 0.015, 0.0});
  const double neighbour = board.albedoAt({1, 0.045, 0.0});
  const double diagonal = board.albedoAt({1, 0.045, 0.03});
  EXPECT_NE(first, neighbour);
  EXPECT_EQ(first, diagonal);
  EXPECT_TRUE(first == 0.8 || first == 0.1);
  EXPECT_FALSE(board.intersect(along({0, 0.07, 0}, {1, 0, 0}), 1e-9, 10, hit));  // off the board
}

TEST(Scene, NearestSurfaceWinsAndShadowsAreFound) {
  Scene scene;
  const Material wall{0.8, {0.8, 0.8, 0.8}}, ball{0.3, {0.5, 0.5, 0.5}};
  scene.add(std::make_unique<Plane>(Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(-1, 0, 0), wall));
  scene.add(std::make_unique<Sphere>(Eigen::Vector3d(2, 0, 0), 0.5, ball));
  Hit hit;
  ASSERT_TRUE(scene.intersect(along({0, 0, 0}, {1, 0, 0}), hit));
  EXPECT_NEAR(hit.distance, 1.5, 1e-12);
  EXPECT_EQ(hit.surface, scene.surfaces()[1].get());
  EXPECT_EQ(hit.surface_index, 1);
  EXPECT_TRUE(scene.occluded({0, 0, 0}, {3, 0, 0}));
  EXPECT_FALSE(scene.occluded({0, 1, 0}, {3, 1, 0}));
}

TEST(Scene, LoaderNamesTheBadObjectAndKey) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("body_scan_test_scene_" + std::to_string(::getpid()) + ".yaml");
  auto message = [&](const std::string& yaml) {
    std::ofstream(path) << yaml;
    try {
      loadScene(path.string());
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("objects:\n  - type: torus\n").find("unknown type 'torus'"), std::string::npos);
  EXPECT_NE(message("objects:\n  - type: sphere\n    center: [1, 0]\n    radius: 0.1\n")
                .find("objects[0]: 'center' must be a list of 3 numbers"),
            std::string::npos);
  EXPECT_NE(message("objects:\n  - type: sphere\n    center: [1, 0, 0]\n    radius: -1\n")
                .find("'radius' must be > 0"),
            std::string::npos);
  EXPECT_NE(message("things: []\n").find("needs a list 'objects:'"), std::string::npos);
  EXPECT_NE(message("objects: [unclosed\n").find("cannot read scene file"), std::string::npos);
  std::ofstream(path) << "objects:\n  - {type: cylinder, base: [0, 0, 0], axis: [0, 0, 1], "
                         "radius: 0.2, height: 1.8, name: calibration_cylinder}\n";
  const Scene scene = loadScene(path.string());
  ASSERT_EQ(scene.surfaces().size(), 1u);
  EXPECT_EQ(scene.surfaces()[0]->name, "calibration_cylinder");
  std::filesystem::remove(path);
}
