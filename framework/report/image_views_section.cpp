// The camera views section of the calibration page (sections.hpp: image_views_html).
#include <algorithm>
#include <cmath>
#include <numeric>

#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/sections.hpp"

namespace kincal::report {

namespace {

// Views drawn at most: a page of thumbnails stays light (a few kB each). With more, the
// views with the largest RMS are drawn, in data order.
constexpr std::size_t kMaxDrawn = 60;
constexpr double kPanelWidth = 320;  // px on the page, the thumbnails' width

// The magnification that makes the largest residual about 12 % of the image's larger side,
// rounded down to 1, 2 or 5 times a power of ten (at least 1).
double magnification(const ImageViews& views) {
  double largest = 0;
  for (const ImageView& v : views.views)
    for (std::size_t i = 0; i < v.measured.size() && i < v.predicted.size(); ++i)
      largest = std::max(largest, (v.predicted[i] - v.measured[i]).norm());
  const double side = std::max(views.width, views.height);
  if (!(largest > 0) || !(side > 0)) return 1;
  const double raw = 0.12 * side / largest;
  if (raw <= 1) return 1;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (double step : {5.0, 2.0, 1.0})
    if (step * decade <= raw) return step * decade;
  return decade;
}

std::string view_svg(const ImageView& v, double width, double height, double scale) {
  const double panel_height = kPanelWidth * height / width;
  std::string svg = format_text(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"-0.5 -0.5 %g %g\" width=\"%g\" "
      "height=\"%g\" role=\"img\">",
      width, height, kPanelWidth, panel_height);
  svg += "<title>" + esc(v.label) + (v.image.empty() ? "" : " " + esc(v.image)) +
         format_text(": %d points, RMS %.3f px, max %.3f px", static_cast<int>(v.measured.size()),
                     v.rms_px, v.max_px) +
         "</title>";
  if (!v.thumbnail.empty())
    svg += format_text(
               "<image x=\"-0.5\" y=\"-0.5\" width=\"%g\" height=\"%g\" "
               "preserveAspectRatio=\"none\" href=\"",
               width, height) +
           esc(v.thumbnail) + "\"/>";
  else
    svg += format_text("<rect class=\"blank\" x=\"-0.5\" y=\"-0.5\" width=\"%g\" height=\"%g\"/>",
                       width, height);
  // Strokes in image px: a line about 1.5 px on the page whatever the image's size.
  const double px = width / kPanelWidth;
  for (std::size_t i = 0; i < v.measured.size() && i < v.predicted.size(); ++i) {
    const Eigen::Vector2d a = v.measured[i];
    const Eigen::Vector2d b = a + scale * (v.predicted[i] - a);
    svg += format_text(
        "<circle class=\"seen\" cx=\"%.2f\" cy=\"%.2f\" r=\"%.2f\" "
        "stroke-width=\"%.2f\"/>",
        a.x(), a.y(), 2 * px, 0.8 * px);
    svg += format_text(
        "<line class=\"residual\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" "
        "stroke-width=\"%.2f\"/>",
        a.x(), a.y(), b.x(), b.y(), 1.5 * px);
  }
  return svg + "</svg>";
}

}  // namespace

std::string image_views_html(const ImageViews& views) {
  std::string out = "<h3>" + esc(views.sensor) + "</h3>";
  out += "<p>" +
         format_text(
             "%d points in %d views of %g x %g px: reprojection error mean %s px, RMS %s "
             "px, max %s px.",
             views.points, static_cast<int>(views.views.size()), views.width, views.height,
             fmt(views.mean_px).c_str(), fmt(views.rms_px).c_str(), fmt(views.max_px).c_str()) +
         "</p>";
  if (views.views.empty() || !(views.width > 0) || !(views.height > 0)) return out;
  // The views drawn: all, or the kMaxDrawn with the largest RMS, in data order.
  std::vector<std::size_t> drawn(views.views.size());
  std::iota(drawn.begin(), drawn.end(), 0);
  if (drawn.size() > kMaxDrawn) {
    const auto key = [&](std::size_t i) {
      const double r = views.views[i].rms_px;
      return std::isnan(r) ? -1.0 : r;
    };
    std::stable_sort(drawn.begin(), drawn.end(),
                     [&](std::size_t a, std::size_t b) { return key(a) > key(b); });
    drawn.resize(kMaxDrawn);
    std::sort(drawn.begin(), drawn.end());
  }
  const double scale = magnification(views);
  bool thumbnails = false;
  for (std::size_t i : drawn) thumbnails = thumbnails || !views.views[i].thumbnail.empty();
  out +=
      "<p class=\"small\">Each view: the points measured (blue circles) and their residuals, "
      "measured to predicted by the calibrated model, in red, magnified " +
      fmt(scale, 3) + " times" +
      (thumbnails ? ", on the image" : " (the images were not at hand: a blank frame)") +
      (drawn.size() < views.views.size()
           ? format_text("; the %d views with the largest RMS of %d",
                         static_cast<int>(drawn.size()), static_cast<int>(views.views.size()))
           : std::string()) +
      ". A pattern shared by the arrows of a view (all one way, a rotation, growing to the "
      "edges) is a model error: the view's pose, the mounts or the lens; noise points "
      "every way.</p>";
  out += "<div class=\"views\">";
  for (std::size_t i : drawn) {
    const ImageView& v = views.views[i];
    out += "<figure class=\"view\">" + view_svg(v, views.width, views.height, scale) +
           "<figcaption>" + esc(v.label) + (v.image.empty() ? "" : "<br>" + esc(v.image)) + "<br>" +
           format_text("RMS %s px, max %s px", fmt(v.rms_px).c_str(), fmt(v.max_px).c_str()) +
           "</figcaption></figure>";
  }
  out += "</div>";
  out +=
      "<table><tr><th class=\"name\">view</th><th class=\"name\">image</th><th>points</th>"
      "<th>mean px</th><th>RMS px</th><th>max px</th></tr>";
  for (const ImageView& v : views.views)
    out += "<tr><td class=\"name\">" + esc(v.label) + "</td><td class=\"name\">" + esc(v.image) +
           "</td><td>" + std::to_string(v.measured.size()) + "</td><td>" + fmt(v.mean_px) +
           "</td><td>" + fmt(v.rms_px) + "</td><td>" + fmt(v.max_px) + "</td></tr>";
  return out + "</table>";
}

}  // namespace kincal::report
