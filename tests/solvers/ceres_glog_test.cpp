// The Ceres backend and glog, whose flags belong to the host program: a solve leaves them as
// it found them, and stays quiet by other means (solvers/ceres_solver.cpp). Built only with
// the Ceres backend, which brings glog.

#ifdef KINCAL_WITH_CERES

#include <glog/logging.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kincal/framework/least_squares/solver_registry.hpp"
#include "solver_fixtures.hpp"

namespace kincal {
namespace {

// The same fit whose residuals are NaN (not refused) beyond a = 1.5: trial points there are
// what Ceres' own evaluation check warns about through glog.
class NanBeyondFence : public kincal::testing::ExponentialFit {
 public:
  bool evaluate_block(int block, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
    ExponentialFit::evaluate_block(block, x, residuals, jacobian, why);
    if (x[0] > 1.5) residuals[0] = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
};

struct GlogFlags {
  int minloglevel = FLAGS_minloglevel;
  bool logtostderr = FLAGS_logtostderr;
  bool alsologtostderr = FLAGS_alsologtostderr;
  int stderrthreshold = FLAGS_stderrthreshold;
  int v = FLAGS_v;
  bool operator==(const GlogFlags& o) const {
    return minloglevel == o.minloglevel && logtostderr == o.logtostderr &&
           alsologtostderr == o.alsologtostderr && stderrthreshold == o.stderrthreshold && v == o.v;
  }
};

class CeresAndGlog : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string why = kincal::testing::why_not_built("ceres");
    if (!why.empty()) GTEST_SKIP() << why;
    saved_ = GlogFlags{};
  }
  void TearDown() override {
    FLAGS_minloglevel = saved_.minloglevel;
    FLAGS_logtostderr = saved_.logtostderr;
  }
  GlogFlags saved_;
};

// A host that chose its own levels (here: everything from INFO, not to stderr only) keeps
// them through solves of every verbosity, including solves meeting uncomputable and NaN
// trial points.
TEST_F(CeresAndGlog, SolvesLeaveTheHostsFlagsAsTheyWere) {
  FLAGS_minloglevel = google::GLOG_INFO;
  FLAGS_logtostderr = false;
  const GlogFlags host;
  const auto solver = SolverRegistry::global().create("ceres");
  for (int verbosity : {0, 1, 2}) {
    SolverOptions options;
    options.verbosity = verbosity;
    kincal::testing::FencedFit fenced;
    NanBeyondFence nan;
    for (const LeastSquaresProblem* problem :
         std::initializer_list<const LeastSquaresProblem*>{&fenced, &nan}) {
      VectorXd x = kincal::testing::ExponentialFit::start();
      ::testing::internal::CaptureStderr();
      const Summary summary = solver->solve(*problem, x, options);
      const std::string err = ::testing::internal::GetCapturedStderr();
      EXPECT_TRUE(GlogFlags{} == host) << "verbosity " << verbosity;
      EXPECT_LE(x[0], 1.5) << summary.brief_report();
      // Quiet without touching the flags: at verbosity 0 nothing at all reaches stderr,
      // although glog would print Ceres' warnings there.
      if (verbosity == 0) {
        EXPECT_EQ(err, "") << summary.brief_report();
      }
    }
  }
}

}  // namespace
}  // namespace kincal

#endif  // KINCAL_WITH_CERES
