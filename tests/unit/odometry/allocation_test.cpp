// The motion prior runs on the rig's hot path: Add and Between must not allocate.
#include <gtest/gtest.h>

#include "algorithms/odometry/motion_prior.hpp"
#include "tests/support/allocation_counter.hpp"

namespace bimslam::odometry {
namespace {

TEST(HotPath, MotionPriorDoesNotAllocate) {
    MotionPrior prior;
    BodyMotionSample s;
    s.attitude = Eigen::Quaterniond::Identity();
    const size_t before = test::Allocations();
    for (int k = 0; k < 10000; ++k) {  // wraps the ring buffer twice
        s.t_ns = int64_t(k) * 10'000'000;
        s.v_xy = {1.0, 0.1};
        ASSERT_TRUE(prior.Add(s).ok());
        if (k > 10) {
            ASSERT_TRUE(prior.Between(s.t_ns - 95'000'000, s.t_ns).has_value());
        }
    }
    EXPECT_EQ(test::Allocations() - before, 0u);
}

}  // namespace
}  // namespace bimslam::odometry
