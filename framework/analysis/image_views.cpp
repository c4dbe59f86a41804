#include "kincal/framework/analysis/image_views.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "kincal/framework/base/format_text.hpp"

namespace kincal {

namespace {

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

}  // namespace

void summarise_image_views(ImageViews& views) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double sum = 0, sum_squares = 0, largest = 0;
  int count = 0;
  for (ImageView& view : views.views) {
    double s = 0, s2 = 0, m = 0;
    const std::size_t k = std::min(view.measured.size(), view.predicted.size());
    for (std::size_t i = 0; i < k; ++i) {
      const double d = (view.predicted[i] - view.measured[i]).norm();
      s += d;
      s2 += d * d;
      m = std::max(m, d);
    }
    view.mean_px = k ? s / k : nan;
    view.rms_px = k ? std::sqrt(s2 / k) : nan;
    view.max_px = k ? m : nan;
    sum += s;
    sum_squares += s2;
    largest = std::max(largest, m);
    count += static_cast<int>(k);
  }
  views.points = count;
  views.mean_px = count ? sum / count : nan;
  views.rms_px = count ? std::sqrt(sum_squares / count) : nan;
  views.max_px = count ? largest : nan;
}

std::string image_views_text(const ImageViews& views, int worst) {
  std::string out = format_text(
      "reprojection error of %s: %d points in %d views, mean %.3f px, RMS %.3f px, max %.3f px\n",
      views.sensor.c_str(), views.points, static_cast<int>(views.views.size()), views.mean_px,
      views.rms_px, views.max_px);
  std::vector<int> order(views.views.size());
  std::iota(order.begin(), order.end(), 0);
  const auto key = [&](int i) {  // a view without a point (NaN) last
    const double r = views.views[i].rms_px;
    return std::isnan(r) ? -1.0 : r;
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) > key(b); });
  const int shown = std::min<int>(std::max(worst, 0), static_cast<int>(order.size()));
  if (shown == 0) return out;
  out += shown == static_cast<int>(order.size())
             ? "  per view, largest RMS first:\n"
             : format_text("  the %d views with the largest RMS (every view in the JSON report):\n",
                           shown);
  for (int i = 0; i < shown; ++i) {
    const ImageView& v = views.views[order[i]];
    out += format_text("    %-24s %3d points  mean %7.3f  RMS %7.3f  max %7.3f px%s%s\n",
                       v.label.c_str(), static_cast<int>(v.measured.size()), v.mean_px, v.rms_px,
                       v.max_px, v.image.empty() ? "" : "  ", v.image.c_str());
  }
  return out;
}

nlohmann::ordered_json image_views_json(const ImageViews& views) {
  nlohmann::ordered_json j;
  j["sensor"] = views.sensor;
  j["width"] = views.width;
  j["height"] = views.height;
  j["points"] = views.points;
  j["mean_px"] = number(views.mean_px);
  j["rms_px"] = number(views.rms_px);
  j["max_px"] = number(views.max_px);
  j["views"] = nlohmann::ordered_json::array();
  for (const ImageView& v : views.views)
    j["views"].push_back({{"label", v.label},
                          {"image", v.image},
                          {"points", v.measured.size()},
                          {"mean_px", number(v.mean_px)},
                          {"rms_px", number(v.rms_px)},
                          {"max_px", number(v.max_px)}});
  return j;
}

}  // namespace kincal
