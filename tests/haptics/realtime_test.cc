// One haptic tick allocates nothing (STYLE.md: the real-time loop), for every method, with and without the
// passivity controller, in contact and in free space.

#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "haptics/rendering/renderer_factory.h"
#include "test_util.h"
#include "tests/support/alloc_counter.h"

namespace robossis::haptics {
namespace {

using testing::Config;
using testing::Home;
using testing::IdentityMap;
using testing::Rsr;

TEST(RealTime, TickAllocatesNothing) {
  for (const std::string& method : KnownMethods()) {
    if (method == "mesh") continue;  // covered in mesh_wall_test.cc with its atlas
    HapticsConfig config = Config();
    config.cloud.translation_points = 50;
    config.cloud.rotation_points = 50;
    std::unique_ptr<HapticRenderer> r = MakeRenderer(method, config, Rsr(), IdentityMap(), 1000);
    r->Reset(Home());
    HapticInput in;
    HapticOutput out;
    robossis::testing::AllocationCounter counter;
    for (int k = 0; k < 400; ++k) {
      // From home out beyond the +x edge and back, with some rotation: free space, contact, deep.
      const double s = 0.0008 * (k < 200 ? k : 400 - k);
      in.X_OH = Home();
      in.X_OH.translation().x() += s;
      in.X_OH.linear() = RotationFromVector(Eigen::Vector3d(0.002 * k, 0, 0));
      in.v_O = Eigen::Vector3d(k < 200 ? 0.8 : -0.8, 0, 0);
      r->Tick(in, out);
    }
    EXPECT_EQ(counter.count(), 0u) << method;
  }
}

}  // namespace
}  // namespace robossis::haptics
