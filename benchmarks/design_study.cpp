// kincal-design-study: the Monte Carlo of issue 13 — the paper's cases 3-5 at equal
// configuration count and noise, with configurations drawn at random (the paper) or chosen
// by experiment design, with and without the prior (the manufacturing tolerance, std 5/sqrt(3)
// mm, the spread of the simulated parameter errors), each beside its predicted bound.
// Writes <out>/runs.csv (one line per case, variant and seed) and <out>/summary.json;
// benchmarks/plot_design_study.py makes the table and the plots of docs/experiment-design.md.

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

struct Variant {
  std::string name;
  bool designed = false;
  DesignCriterion criterion = DesignCriterion::kD;
  bool prior = false;
};

const std::vector<Variant>& variants() {
  static const std::vector<Variant> v = {
      {"random", false, DesignCriterion::kD, false},
      {"D", true, DesignCriterion::kD, false},
      {"I", true, DesignCriterion::kI, false},
      {"random+prior", false, DesignCriterion::kD, true},
      {"D+prior", true, DesignCriterion::kD, true},
      {"I+prior", true, DesignCriterion::kI, true},
  };
  return v;
}

struct Run {
  int case_id = 0, seed = 0;
  std::string variant;
  double before_mean = 0, after_mean = 0, after_rms = 0, predicted_rms = 0;
  double after_orientation_rms = 0, predicted_orientation_rms = 0;
  std::string termination;
};

// RMS position and orientation errors over the validation set, and the bound's prediction
// there: Cov = (J^T J / sigma^2 + prior)^-1 at the true parameters, through J_pose_params.
void evaluate(const Scenario& s, const VectorXd& estimate, const VectorXd& prior_std, Run& run) {
  const Mechanism& mech = s.model->mechanism();
  const int n_mech = mech.num_parameters();
  const int count = static_cast<int>(s.validation_poses.size());
  double p2 = 0, o2 = 0;
  for (int j = 0; j < count; ++j) {
    const ForwardKinematicsResult fk =
        mech.forward_kinematics(estimate.head(n_mech), s.validation_actuators.row(j).transpose(),
                                mech.home_pose(), s.model->forward_kinematics_options());
    if (!fk.ok()) {
      p2 = o2 = INFINITY;
      break;
    }
    p2 += (fk.pose.translation - s.validation_poses[j].translation).squaredNorm();
    o2 += log_so3(fk.pose.rotation * s.validation_poses[j].rotation.transpose()).squaredNorm();
  }
  run.after_rms = std::sqrt(p2 / count);
  run.after_orientation_rms = std::sqrt(o2 / count);

  const auto problem = s.make_problem();
  const VectorXd x_true = problem->free_parameters(s.truth);
  VectorXd r;
  MatrixXd J;
  if (!problem->evaluate(x_true, &r, &J)) {
    run.predicted_rms = NAN;
    return;
  }
  // The problem's residuals are divided by the model's reading_std when it states one (a
  // scenario with a prior always does): then J is already whitened.
  const double sigma =
      s.model->weighted() ? 1.0 : s.options.noise_for(kincal::kMillimetre) / std::sqrt(3.0);
  MatrixXd info = J.transpose() * J / (sigma * sigma);
  if (prior_std.size()) info.diagonal().array() += prior_std.array().square().inverse();
  const MatrixXd cov = info.ldlt().solve(MatrixXd::Identity(info.rows(), info.cols()));
  WorkspaceSamples w;
  Matrix6Xd Jp(6, n_mech);
  for (int j = 0; j < count; ++j) {
    mech.pose_jacobian_params(s.truth.head(n_mech), s.validation_actuators.row(j).transpose(),
                              s.validation_poses[j], Jp);
    Matrix6Xd Jf(6, s.free_indices.size());
    for (std::size_t c = 0; c < s.free_indices.size(); ++c) Jf.col(c) = Jp.col(s.free_indices[c]);
    w.J_free.push_back(Jf);
  }
  const PoseErrorPrediction p = predict_pose_errors(w, cov);
  run.predicted_rms = p.position_rms;
  run.predicted_orientation_rms = p.orientation_rms;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace
}  // namespace kincal

int main(int argc, char** argv) {
  using namespace kincal;
  int seeds = 200, candidates = 10000, validation = 200, threads = 1, bound_iterations = 500;
  std::uint64_t design_seed = 1;
  std::vector<int> cases = {3, 4, 5};
  std::string out_dir = "design-study";
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--seeds")
      seeds = std::stoi(value());
    else if (a == "--candidates")
      candidates = std::stoi(value());
    else if (a == "--validation")
      validation = std::stoi(value());
    else if (a == "--threads")
      threads = std::stoi(value());
    else if (a == "--bound-iterations")
      bound_iterations = std::stoi(value());
    else if (a == "--design-seed")
      design_seed = std::stoull(value());
    else if (a == "--out")
      out_dir = value();
    else if (a == "--quiet")
      quiet = true;
    else if (a == "--cases") {
      cases.clear();
      std::stringstream in(value());
      for (std::string c; std::getline(in, c, ',');) cases.push_back(std::stoi(c));
    } else {
      std::cerr << "usage: kincal-design-study [--seeds N=200] [--cases 3,4,5] [--candidates "
                   "K=10000] [--design-seed S=1] [--validation N=200] [--threads N=1] [--out DIR] "
                   "[--bound-iterations N=500] [--quiet]\n";
      return 2;
    }
  }
  std::filesystem::create_directories(out_dir);
  const auto base_model = make_cube_hexapod();
  const double prior_std_mm = 5 / std::sqrt(3.0);

  // One design per case and variant, made once on the nominal model (the truth is unknown
  // when measurements are planned) and measured on every simulated machine, as an engineer
  // would: the seeds vary the machine's errors, the noise and the validation poses.
  std::map<std::pair<int, int>, Measurements> designs;
  struct BoundRow {
    double criterion, bound, std_ratio;
    int iterations;
  };
  std::map<std::pair<int, int>, BoundRow> design_bounds;
  for (int c : cases)
    for (int v = 0; v < static_cast<int>(variants().size()); ++v) {
      const Variant& variant = variants()[v];
      if (!variant.designed) continue;
      const PaperCase& pc = paper_case(c);
      auto model = std::make_shared<MeasurementModel>(*base_model);
      if (variant.prior)
        model->parameters().for_each_matching("*", [&](Parameter& p) {
          if (p.free) p.prior_std = prior_std_mm;
        });
      DesignOptions d;
      d.criterion = variant.criterion;
      d.count = pc.num_configurations;
      d.num_random = candidates;
      d.seed = design_seed;
      d.noise_std = VectorXd::Constant(1, pc.noise_half_width / std::sqrt(3.0));
      const DesignRun run = run_design(*model, d);
      designs[{c, v}] = run.rows;
      // How far the exchange is from the best any design of these candidates can be.
      const DesignBound bound =
          design_bound(run.candidates, run.setup, d, run.result.chosen, bound_iterations);
      const double std_ratio =
          design_std_ratio_to_bound(d.criterion, run.result.criterion_value, bound,
                                    static_cast<int>(run.setup.free_indices.size()));
      design_bounds[{c, v}] = {run.result.criterion_value, bound.bound, std_ratio,
                               bound.iterations};
      if (!quiet)
        std::printf(
            "case %d %-13s design: %d passes, %d exchanges, criterion %.6g (greedy %.6g), "
            "bound %.6g after %d Frank-Wolfe iterations (std ratio to the bound %.4f)\n",
            c, variant.name.c_str(), run.result.passes, run.result.exchanges,
            run.result.criterion_value, run.result.greedy_value, bound.bound, bound.iterations,
            std_ratio);
    }

  std::vector<Run> runs;
  std::mutex mutex;
  struct Job {
    int case_id, variant, seed;
  };
  std::vector<Job> jobs;
  for (int c : cases)
    for (int v = 0; v < static_cast<int>(variants().size()); ++v)
      for (int s = 1; s <= seeds; ++s) jobs.push_back({c, v, s});
  parallel_for(
      static_cast<int>(jobs.size()), threads,
      [&](int index) {
        const Job& job = jobs[index];
        const Variant& variant = variants()[job.variant];
        const PaperCase& pc = paper_case(job.case_id);
        const auto model = base_model;
        ScenarioOptions o;
        if (variant.prior) o.prior_std.set(kincal::kMillimetre, prior_std_mm);
        o.num_configurations = pc.num_configurations;
        o.noise_half_width.set(kincal::kMillimetre, pc.noise_half_width);
        o.num_validation = validation;
        o.seed = derive_seed(1, job.seed);  // the same truth, noise and validation per seed
        if (variant.designed) o.planned = designs.at({job.case_id, job.variant});
        const Scenario s = make_scenario(model, o);
        Run run;
        run.case_id = job.case_id;
        run.seed = job.seed;
        run.variant = variant.name;
        run.before_mean = validation_errors(s, s.nominal).position_mean_mm;
        SolverOptions so;
        so.max_iterations = 200;
        // With a prior, run_calibration solves the MAP problem (PriorProblem).
        const auto solver = SolverRegistry::global().create("lm");
        const CalibrationRun cal = run_calibration(s, *solver, so, false);
        const VectorXd& estimate = cal.estimate;
        VectorXd prior_std;
        if (variant.prior) prior_std = VectorXd::Constant(s.free_indices.size(), prior_std_mm);
        run.termination = to_string(cal.summary.termination);
        run.after_mean = cal.after.position_mean_mm;
        evaluate(s, estimate, prior_std, run);
        std::lock_guard<std::mutex> lock(mutex);
        runs.push_back(run);
      },
      quiet ? nullptr : "design study");
  std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) {
    return std::tie(a.case_id, a.variant, a.seed) < std::tie(b.case_id, b.variant, b.seed);
  });
  std::ofstream csv(out_dir + "/runs.csv");
  csv << "case,variant,seed,before_mean_mm,after_mean_mm,after_rms_mm,predicted_rms_mm,"
         "after_orientation_rms_rad,predicted_orientation_rms_rad,termination\n";
  for (const Run& r : runs)
    csv << r.case_id << "," << r.variant << "," << r.seed << "," << r.before_mean << ","
        << r.after_mean << "," << r.after_rms << "," << r.predicted_rms << ","
        << r.after_orientation_rms << "," << r.predicted_orientation_rms << "," << r.termination
        << "\n";
  nlohmann::ordered_json summary;
  summary["seeds"] = seeds;
  summary["candidates"] = candidates;
  summary["design_seed"] = design_seed;
  summary["validation"] = validation;
  summary["cells"] = nlohmann::ordered_json::array();
  for (int c : cases)
    for (int vi = 0; vi < static_cast<int>(variants().size()); ++vi) {
      const Variant& v = variants()[vi];
      std::vector<double> before, after, rms, predicted;
      double ms = 0, pms = 0;
      int worse = 0, n = 0, failed = 0;
      for (const Run& r : runs) {
        if (r.case_id != c || r.variant != v.name) continue;
        before.push_back(r.before_mean);
        after.push_back(r.after_mean);
        rms.push_back(r.after_rms);
        predicted.push_back(r.predicted_rms);
        ms += r.after_rms * r.after_rms;
        pms += r.predicted_rms * r.predicted_rms;
        worse += r.after_mean > r.before_mean;
        failed += r.termination != "converged" && r.termination != "max_iterations";
        ++n;
      }
      summary["cells"].push_back({{"case", c},
                                  {"variant", v.name},
                                  {"runs", n},
                                  {"median_before_mm", median(before)},
                                  {"median_after_mm", median(after)},
                                  {"median_after_rms_mm", median(rms)},
                                  {"median_predicted_rms_mm", median(predicted)},
                                  {"mc_rms_mm", std::sqrt(ms / n)},
                                  {"predicted_rms_mm", std::sqrt(pms / n)},
                                  {"worse_than_nominal", worse},
                                  {"solver_failures", failed}});
      if (design_bounds.count({c, vi})) {
        const BoundRow& b = design_bounds.at({c, vi});
        auto& cell = summary["cells"].back();
        cell["design_criterion"] = b.criterion;
        cell["design_criterion_bound"] = b.bound;
        cell["design_std_ratio_to_bound"] = b.std_ratio;
        cell["bound_iterations"] = b.iterations;
      }
      if (!quiet)
        std::printf(
            "case %d %-13s median after %8.4f mm (before %.3f), MC RMS %8.4f, predicted "
            "%8.4f mm, worse than nominal %d/%d\n",
            c, v.name.c_str(), median(after), median(before), std::sqrt(ms / n), std::sqrt(pms / n),
            worse, n);
    }
  std::ofstream(out_dir + "/summary.json") << summary.dump(2) << "\n";
  return 0;
}
