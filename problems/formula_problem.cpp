#include "kincal/problems/formula_problem.hpp"

#include <stdexcept>

namespace kincal::problems {
namespace {

class FormulaProblem final : public TestProblem {
 public:
  explicit FormulaProblem(ProblemSpec spec)
      : TestProblem(spec.name, spec.title, spec.number, spec.n, spec.m, spec.start),
        residuals_(std::move(spec.residuals)) {
    if (!residuals_ || spec.minima.empty())
      throw std::logic_error("test problem " + spec.name + ": no residuals or no minimum");
    for (auto& minimum : spec.minima) add_minimum(std::move(minimum));
    set_note(std::move(spec.note));
  }

 protected:
  bool compute(const VectorXd& x, Eigen::Ref<VectorXd> r, Eigen::Ref<MatrixXd>* jacobian,
               std::string* why) const override {
    if (jacobian) jacobian->setZero();
    return residuals_(x, r, jacobian, why);
  }

 private:
  ResidualFunction residuals_;
};

}  // namespace

std::shared_ptr<const TestProblem> make_problem(ProblemSpec spec) {
  return std::make_shared<FormulaProblem>(std::move(spec));
}

}  // namespace kincal::problems
