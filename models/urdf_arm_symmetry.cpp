// The discrete symmetries of an imported arm's parametrisation (UrdfArm::nearer_equivalent).
//
// T(q) = B prod_i [C_i E_i M_i(q_i + o_i)] C_tip T_tool. For a revolute joint i,
// M_i(v + s) = M_i(v) R_i(s) with R_i the rotation about its axis: turning the zero offset o_i
// by s = +-pi turns everything after joint i by pi about that axis, which the rest of the chain
// undoes with a pending rotation L = R_i(-s) on its left. Where it is undone decides how the
// links are drawn, not where the tool is:
//   (a) in the next origin error:  E_j' = C_j^-1 L C_j E_j                      (done)
//   (b) carried through joint j:   E_j' = C_j^-1 L C_j E_j K, K = R_j(pi), which commutes
//                                  with joint j's motion; L <- K^-1 for the rest
//   (c) as (b), then in joint j's zero: o_j' = o_j +- pi undoes K                (done)
//   (d) in the tool frame:         T_tool' = C_tip^-1 L C_tip T_tool           (done)
//   (e) before joint i, in its own origin error: E_i' = E_i R_i(-s)           (done)
// A solver that wanders far can end on the other branch, e.g. o_i = pi with the next origins'
// translations reversed (Rz(pi) Tx(-a) = Tx(a) Rz(pi)): the same fit, links drawn backwards.
// The search below tries, for each joint whose zero lies more than pi/2 from its nominal, every
// way to undo the turn, keeps the maps that change only changeable parameters, and applies the
// one nearest nominal, until none is nearer.
#include <cmath>
#include <limits>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {

namespace {

Pose rotation_about(const Vector3d& axis, double angle) {
  Pose r;
  r.rotation = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  return r;
}

// Frame parameters of `frame` on the Z-Y-X Euler branch nearest `near` (both branches of
// the angles, each angle wrapped to near's +- pi): the map moves a frame's angles as little as
// the rotation allows.
Vector6d frame_parameters_near(const Pose& frame, const Vector6d& near) {
  const Vector6d first = frame_parameters(frame);
  Vector6d second = first;
  // R = Rz(a) Ry(b) Rx(g) = Rz(a + pi) Ry(pi - b) Rx(g + pi).
  second[3] = first[3] + kPi;
  second[4] = kPi - first[4];
  second[5] = first[5] + kPi;
  Vector6d best = first;
  double best_distance = std::numeric_limits<double>::infinity();
  for (Vector6d candidate : {first, second}) {
    double distance = 0;
    for (int k = 3; k < 6; ++k) {
      candidate[k] = near[k] + wrap_angle(candidate[k] - near[k]);
      distance += std::pow(candidate[k] - near[k], 2);
    }
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

}  // namespace

bool UrdfArm::nearer_equivalent(const ParamsRef& params, const ParamsRef& nominal,
                                const std::vector<bool>& changeable, const VectorXd& scale,
                                VectorXd& out, std::string* what) const {
  const int n = num_joints();
  const auto distance = [&](const VectorXd& p) {
    double sum = 0;
    for (int k = 0; k < p.size(); ++k) {
      double d = p[k] - nominal[k];
      if (parameters_[k].unit == kRadian) d = wrap_angle(d);
      sum += std::pow(d / scale[k], 2);
    }
    return sum;
  };
  // A candidate counts only if every parameter it changes may change.
  const auto admissible = [&](const VectorXd& from, const VectorXd& to) {
    for (int k = 0; k < to.size(); ++k) {
      double d = to[k] - from[k];
      if (parameters_[k].unit == kRadian) d = wrap_angle(d);
      if (std::abs(d) > 1e-12 * (1 + std::abs(from[k])) && !changeable[k]) return false;
    }
    return true;
  };
  const auto origin_error = [&](const VectorXd& p, int j) {
    return frame_from_parameters(p.segment<6>(joint_index(j)));
  };
  // A zero moved by +-pi, the sign that brings it nearer its nominal.
  const auto half_turn_toward = [&](const VectorXd& p, int j) {
    const int o = joint_index(j) + kOffset;
    return wrap_angle(p[o] - nominal[o]) > 0 ? -kPi : kPi;
  };

  VectorXd current = params;
  std::string said;
  bool mapped = false;
  // Every frame block on its Z-Y-X Euler branch nearest nominal: (rx, ry, rz) and
  // (rx + pi, pi - ry, rz + pi) are one rotation.
  {
    std::vector<int> blocks = {base_index(), tool_index()};
    for (int j = 0; j < n; ++j) blocks.push_back(joint_index(j));
    std::string frames;
    for (int b : blocks) {
      VectorXd candidate = current;
      candidate.segment<6>(b) = frame_parameters_near(frame_from_parameters(current.segment<6>(b)),
                                                      nominal.segment<6>(b));
      if (!admissible(current, candidate) ||
          !(distance(candidate) < distance(current) * (1 - 1e-12)))
        continue;
      for (int k = 0; k < candidate.size(); ++k)
        if (!changeable[k]) candidate[k] = current[k];
      current = candidate;
      frames += (frames.empty() ? "" : ", ") +
                parameters_[b].name.substr(0, parameters_[b].name.rfind('.'));
    }
    if (!frames.empty()) {
      said = "the angles of " + frames + " written on their other Z-Y-X Euler branch";
      mapped = true;
    }
  }
  double current_distance = distance(current);
  for (int round = 0; round < 2 * n + 2; ++round) {
    VectorXd best;
    double best_distance = current_distance * (1 - 1e-12);
    std::string best_words;
    for (int i = 0; i < n; ++i) {
      if (!is_revolute_joint(i)) continue;
      const int oi = joint_index(i) + kOffset;
      if (std::abs(wrap_angle(current[oi] - nominal[oi])) <= kPi / 2) continue;
      VectorXd start = current;
      const double s = half_turn_toward(current, i);
      start[oi] += s;
      const std::string head = parameters_[oi].name + (s > 0 ? " +pi" : " -pi");
      const auto consider = [&](VectorXd candidate, const std::string& words) {
        if (!admissible(current, candidate)) return;
        // What may not change keeps its value exactly, not a rounding of it.
        for (int k = 0; k < candidate.size(); ++k)
          if (!changeable[k]) candidate[k] = current[k];
        const double d = distance(candidate);
        if (d < best_distance) {
          best_distance = d;
          best = candidate;
          best_words = words;
        }
      };
      {  // (e) joint i's own origin takes the turn back: E_i' = E_i R_i(-s).
        VectorXd p = start;
        const Pose own =
            compose(origin_error(start, i), rotation_about(geometry_.joints[i].axis, -s));
        p.segment<6>(joint_index(i)) =
            frame_parameters_near(own, nominal.segment<6>(joint_index(i)));
        consider(p, head + ", " + geometry_.joints[i].name + "'s origin turned back");
      }
      // Depth-first over where the turn is undone; L pending on the left of the rest.
      struct State {
        VectorXd p;
        int j;
        Pose pending;
        std::string words;
      };
      std::vector<State> stack = {
          {start, i + 1, rotation_about(geometry_.joints[i].axis, -s), head}};
      while (!stack.empty()) {
        State st = std::move(stack.back());
        stack.pop_back();
        if (st.j == n) {
          // (d) the tool frame takes the turn.
          VectorXd p = st.p;
          const Pose tool = frame_from_parameters(p.segment<6>(tool_index()));
          const Pose moved = compose(inverse(tip_), compose(st.pending, compose(tip_, tool)));
          p.segment<6>(tool_index()) = frame_parameters_near(moved, p.segment<6>(tool_index()));
          consider(p, st.words + ", the tool frame turned with it");
          continue;
        }
        const int j = st.j;
        const Pose& C = origins_[j];
        const Pose E = origin_error(st.p, j);
        const Pose turned = compose(inverse(C), compose(st.pending, compose(C, E)));
        const std::string origin = geometry_.joints[j].name + "'s origin";
        {  // (a)
          VectorXd p = st.p;
          p.segment<6>(joint_index(j)) =
              frame_parameters_near(turned, p.segment<6>(joint_index(j)));
          consider(p, st.words + ", " + origin + " turned with it");
        }
        const Pose K = rotation_about(geometry_.joints[j].axis, kPi);
        VectorXd through = st.p;
        through.segment<6>(joint_index(j)) =
            frame_parameters_near(compose(turned, K), through.segment<6>(joint_index(j)));
        if (is_revolute_joint(j)) {  // (c)
          VectorXd p = through;
          p[joint_index(j) + kOffset] += half_turn_toward(through, j);
          consider(p, st.words + ", " + origin + " turned with it and " +
                          parameters_[joint_index(j) + kOffset].name + " turned back");
        }
        // (b) the turn carried on.
        stack.push_back({through, j + 1, rotation_about(geometry_.joints[j].axis, -kPi),
                         st.words + ", " + origin + " turned with it"});
      }
    }
    if (best.size() == 0) break;
    current = best;
    current_distance = best_distance;
    said += (said.empty() ? "" : "; ") + best_words;
    mapped = true;
  }
  if (!mapped) return false;
  out = current;
  if (what) *what = said;
  return true;
}

}  // namespace kincal
