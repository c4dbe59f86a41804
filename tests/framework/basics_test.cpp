// Parameters, pose helpers, robust losses, statistics, the registry and parallel_for.

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/base/statistics.hpp"
#include "kincal/framework/kinematics/parameters.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/least_squares/robust_loss.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"

namespace kincal {
namespace {

TEST(Parameters, GlobMatching) {
  EXPECT_TRUE(glob_match("leg*.offset", "leg4.offset"));
  EXPECT_TRUE(glob_match("leg?.base.*", "leg1.base.z"));
  EXPECT_TRUE(glob_match("*", "gauge.offset"));
  EXPECT_FALSE(glob_match("leg*.offset", "gauge.offset"));
  EXPECT_FALSE(glob_match("leg?.base.x", "leg10.base.x"));
  EXPECT_TRUE(glob_match("gauge.offset", "gauge.offset"));
  EXPECT_FALSE(glob_match("gauge.offse", "gauge.offset"));
}

TEST(Parameters, FreeMaskByPatternAndErrors) {
  ParameterSet set({{"a.x", 1, "mm", false}, {"a.y", 2, "mm", false}, {"b.x", 3, "mm", true}});
  EXPECT_EQ(set.set_free("a.*", true), 2);
  EXPECT_EQ(set.num_free(), 3);
  EXPECT_EQ(set.set_free("b.x", false), 1);
  EXPECT_EQ(set.free_indices(), (std::vector<int>{0, 1}));
  EXPECT_THROW(set.set_free("c.*", true), std::invalid_argument);
  EXPECT_THROW(set.index_of("nope"), std::invalid_argument);
  EXPECT_THROW(ParameterSet({{"a", 0, "mm", false}, {"a", 0, "mm", false}}), std::invalid_argument);
}

TEST(Pose, EulerZyxRoundTripAndExpLog) {
  Random rng(9);
  for (int i = 0; i < 100; ++i) {
    const Vector3d abg(rng.symmetric(3.0), rng.symmetric(1.5), rng.symmetric(3.0));
    EXPECT_LT((euler_zyx(rotation_from_euler_zyx(abg)) - abg).norm(), 1e-12);
    const Vector3d w(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
    EXPECT_LT((log_so3(exp_so3(w)) - w).norm(), 1e-12);
  }
  // Orientation error of the paper: a pure rotation by 0.01 rad about z reads 0.01.
  Pose a, b;
  b.rotation = exp_so3(Vector3d(0, 0, 0.01));
  EXPECT_NEAR(orientation_error(a, b), 0.01, 1e-15);
}

TEST(Pose, ExpSo3MatchesEigensAngleAxisAtEveryScale) {
  // Across the switch to the series at 1e-4 rad, down to the tiny rotations of the last
  // Newton steps and up to half a turn.
  Random rng(10);
  for (double scale : {1e-12, 1e-8, 3e-5, 9.9e-5, 1e-4, 1.01e-4, 1e-3, 0.1, 1.0, 3.0}) {
    for (int i = 0; i < 20; ++i) {
      Vector3d axis(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
      axis.normalize();
      const Vector3d w = scale * axis;
      const Matrix3d expected = Eigen::AngleAxisd(scale, axis).toRotationMatrix();
      EXPECT_LT((exp_so3(w) - expected).cwiseAbs().maxCoeff(), 2e-15) << "angle " << scale;
      EXPECT_LT((exp_so3(w) * exp_so3(w).transpose() - Matrix3d::Identity()).norm(), 4e-15);
    }
  }
}

// frame_block remembers what it computed: it must return exactly frame_from_parameters and
// euler_zyx_angular_jacobian, for more blocks than its table holds (so entries are replaced),
// for keys that differ only in the sign of a zero, and on several threads at once.
TEST(Pose, FrameBlockIsExactlyWhatComputingGives) {
  const auto check = [](int seed, int* mismatches) {
    Random rng(static_cast<std::uint64_t>(seed));
    std::vector<Vector6d> blocks(300);
    for (Vector6d& b : blocks)
      for (int k = 0; k < 6; ++k) b[k] = k < 3 ? rng.symmetric(500.0) : rng.symmetric(3.0);
    blocks[1].setZero();
    blocks[2] = -blocks[1];  // -0.0: other bits, the same frame
    for (int pass = 0; pass < 3; ++pass)
      for (const Vector6d& b : blocks) {
        const FrameBlock got = frame_block(b);
        const Pose frame = frame_from_parameters(b);
        const Matrix3d angular = euler_zyx_angular_jacobian(b.tail<3>());
        if (got.frame.rotation != frame.rotation || got.frame.translation != frame.translation ||
            got.angular_jacobian != angular)
          ++*mismatches;
      }
  };
  int mismatches[3] = {0, 0, 0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 3; ++t) threads.emplace_back(check, t + 1, &mismatches[t]);
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(mismatches[0] + mismatches[1] + mismatches[2], 0);
}

TEST(RobustLoss, ParsesAndRejects) {
  EXPECT_EQ(RobustLoss::parse("none").kind, RobustLoss::Kind::kNone);
  EXPECT_EQ(RobustLoss::parse("huber:0.5").kind, RobustLoss::Kind::kHuber);
  EXPECT_DOUBLE_EQ(RobustLoss::parse("cauchy:2").delta, 2.0);
  for (const char* bad : {"huber", "huber:", "huber:-1", "huber:x", "tukey:1", "cauchy:1e400"})
    EXPECT_THROW(RobustLoss::parse(bad), std::invalid_argument) << bad;
}

TEST(RobustLoss, DerivativesMatchFiniteDifferences) {
  for (const char* text : {"huber:0.7", "cauchy:0.7"}) {
    const RobustLoss loss = RobustLoss::parse(text);
    for (double s : {0.01, 0.3, 0.45, 0.6, 2.0, 10.0}) {
      const double h = 1e-6;
      const auto e = loss.evaluate(s), ep = loss.evaluate(s + h), em = loss.evaluate(s - h);
      EXPECT_NEAR(e[1], (ep[0] - em[0]) / (2 * h), 1e-6) << text << " s=" << s;
      EXPECT_NEAR(e[2], (ep[1] - em[1]) / (2 * h), 1e-5) << text << " s=" << s;
    }
  }
}

TEST(Statistics, Quantiles) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2);
  EXPECT_DOUBLE_EQ(median({4, 1, 2, 3}), 2.5);
  EXPECT_DOUBLE_EQ(quantile({0, 10}, 0.9), 9);
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(Random, DeterministicAndUniform) {
  Random a(5), b(5);
  double sum = 0;
  for (int i = 0; i < 100000; ++i) {
    const double u = a.uniform01();
    EXPECT_EQ(u, b.uniform01());
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
  }
  EXPECT_NEAR(sum / 100000, 0.5, 0.01);
  EXPECT_NE(derive_seed(1, 1), derive_seed(1, 2));
  EXPECT_NE(derive_seed(1, 1), derive_seed(2, 1));
}

TEST(Parallel, VisitsEveryIndexOnceAndPropagatesErrors) {
  std::vector<std::atomic<int>> hits(1000);
  parallel_for(1000, 3, [&](int i) { ++hits[i]; });
  for (auto& h : hits) EXPECT_EQ(h.load(), 1);
  EXPECT_THROW(parallel_for(10, 2,
                            [](int i) {
                              if (i == 7) throw std::runtime_error("boom");
                            }),
               std::runtime_error);
}

TEST(Registry, UnknownNamesAreRejectedWithTheList) {
  try {
    SolverRegistry::global().create("no-such-solver");
    FAIL() << "no exception";
  } catch (const InvalidSolverOptions& e) {
    EXPECT_NE(std::string(e.what()).find("gn"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(SolverRegistry::global().contains("gn"));
  EXPECT_FALSE(SolverRegistry::global().contains("gn:x"));
}

}  // namespace
}  // namespace kincal
