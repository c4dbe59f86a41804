#include "kincal/framework/report/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kincal::report {

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        // Control characters other than tab and line breaks are not allowed in XML.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r')
          out += "\xEF\xBF\xBD";  // U+FFFD
        else
          out += c;
    }
  }
  return out;
}

std::string format_number(double value, int digits) {
  if (!std::isfinite(value)) return "\xE2\x80\x93";  // en dash
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

std::vector<double> nice_ticks(double lo, double hi, int count) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi) || count < 1) return ticks;
  const double raw = (hi - lo) / count;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  // Counted, not accumulated: t += step could stall where step is below t's precision.
  const double first = std::ceil(lo / step);
  for (int k = 0; k <= 2 * count + 2; ++k) {
    const double t = (first + k) * step;
    if (t > hi + 1e-9 * step) break;
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  }
  return ticks;
}

namespace {

std::string px_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

std::string title_element(const std::string& tooltip) {
  return tooltip.empty() ? "" : "<title>" + xml_escape(tooltip) + "</title>";
}

std::string class_attribute(const std::string& css_class) {
  return css_class.empty() ? "" : " class=\"" + xml_escape(css_class) + "\"";
}

}  // namespace

SvgChart::SvgChart(int width, int height, std::string title, int margin_left)
    : width_(width), height_(height), margin_left_(margin_left), title_(std::move(title)) {}

double SvgChart::to_unit(const Axis& a, double v) const {
  if (a.log) {
    const double lo = std::log10(a.lo), hi = std::log10(a.hi);
    const double lv = v > 0 ? std::log10(v) : lo;
    return hi > lo ? (lv - lo) / (hi - lo) : 0.5;
  }
  return a.hi > a.lo ? (v - a.lo) / (a.hi - a.lo) : 0.5;
}

double SvgChart::px(double x) const { return left() + to_unit(x_, x) * (right() - left()); }
double SvgChart::py(double y) const { return bottom() - to_unit(y_, y) * (bottom() - top()); }

void SvgChart::draw_axes(bool x_ticks, bool y_ticks) {
  std::string& b = body_;
  b += "<rect class=\"frame\" x=\"" + px_text(left()) + "\" y=\"" + px_text(top()) + "\" width=\"" +
       px_text(right() - left()) + "\" height=\"" + px_text(bottom() - top()) + "\"/>";
  auto ticks_of = [](const Axis& a) {
    if (!a.log) return nice_ticks(a.lo, a.hi, 5);
    std::vector<double> t;
    if (!(a.lo > 0 && a.hi > a.lo && std::isfinite(a.hi))) return t;
    const int first = static_cast<int>(std::ceil(std::log10(a.lo) - 1e-9));
    const int last = static_cast<int>(std::floor(std::log10(a.hi) + 1e-9));
    const int stride = std::max(1, (last - first) / 6 + 1);
    for (int e = first; e <= last; e += stride) t.push_back(std::pow(10.0, e));
    return t;
  };
  if (x_ticks)
    for (double t : ticks_of(x_)) {
      const double x = px(t);
      b += "<line class=\"grid\" x1=\"" + px_text(x) + "\" y1=\"" + px_text(top()) + "\" x2=\"" +
           px_text(x) + "\" y2=\"" + px_text(bottom()) + "\"/>";
      text_px(x, bottom() + 14, format_number(t, 3), "tick", "middle");
    }
  if (y_ticks)
    for (double t : ticks_of(y_)) {
      const double y = py(t);
      b += "<line class=\"grid\" x1=\"" + px_text(left()) + "\" y1=\"" + px_text(y) + "\" x2=\"" +
           px_text(right()) + "\" y2=\"" + px_text(y) + "\"/>";
      text_px(left() - 4, y + 4, format_number(t, 3), "tick", "end");
    }
  if (!x_.label.empty())
    text_px((left() + right()) / 2, height_ - 8.0, x_.label, "axis-label", "middle");
  if (!y_.label.empty()) text_px(14, (top() + bottom()) / 2, y_.label, "axis-label", "middle", -90);
  text_px(left(), 18, title_, "chart-title");
}

void SvgChart::point(double x, double y, double radius, const std::string& css_class,
                     const std::string& tooltip) {
  body_ += "<circle" + class_attribute(css_class) + " cx=\"" + px_text(px(x)) + "\" cy=\"" +
           px_text(py(y)) + "\" r=\"" + px_text(radius) + "\">" + title_element(tooltip) +
           "</circle>";
}

void SvgChart::line(double x0, double y0, double x1, double y1, const std::string& css_class) {
  body_ += "<line" + class_attribute(css_class) + " x1=\"" + px_text(px(x0)) + "\" y1=\"" +
           px_text(py(y0)) + "\" x2=\"" + px_text(px(x1)) + "\" y2=\"" + px_text(py(y1)) + "\"/>";
}

void SvgChart::rect(double x0, double y0, double x1, double y1, const std::string& css_class,
                    const std::string& tooltip) {
  const double a = px(x0), b = px(x1), c = py(y0), d = py(y1);
  body_ += "<rect" + class_attribute(css_class) + " x=\"" + px_text(std::min(a, b)) + "\" y=\"" +
           px_text(std::min(c, d)) + "\" width=\"" + px_text(std::abs(b - a)) + "\" height=\"" +
           px_text(std::abs(d - c)) + "\">" + title_element(tooltip) + "</rect>";
}

void SvgChart::polyline(const std::vector<std::pair<double, double>>& points,
                        const std::string& css_class) {
  std::string coordinates;
  for (const auto& [x, y] : points) coordinates += px_text(px(x)) + "," + px_text(py(y)) + " ";
  body_ += "<polyline" + class_attribute(css_class) + " points=\"" + coordinates + "\"/>";
}

void SvgChart::text(double x, double y, const std::string& text, const std::string& css_class,
                    const std::string& anchor) {
  text_px(px(x), py(y), text, css_class, anchor);
}

void SvgChart::text_px(double x, double y, const std::string& text, const std::string& css_class,
                       const std::string& anchor, double rotate_deg) {
  body_ += "<text" + class_attribute(css_class) + " x=\"" + px_text(x) + "\" y=\"" + px_text(y) +
           "\" text-anchor=\"" + xml_escape(anchor) + "\"";
  if (rotate_deg != 0)
    body_ +=
        " transform=\"rotate(" + px_text(rotate_deg) + " " + px_text(x) + " " + px_text(y) + ")\"";
  body_ += ">" + xml_escape(text) + "</text>";
}

void SvgChart::cell_px(double x, double y, double w, double h, const std::string& fill,
                       const std::string& tooltip) {
  body_ += "<rect x=\"" + px_text(x) + "\" y=\"" + px_text(y) + "\" width=\"" + px_text(w) +
           "\" height=\"" + px_text(h) + "\" fill=\"" + xml_escape(fill) + "\">" +
           title_element(tooltip) + "</rect>";
}

std::string SvgChart::str() const {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width_) +
         "\" height=\"" + std::to_string(height_) + "\" viewBox=\"0 0 " + std::to_string(width_) +
         " " + std::to_string(height_) + "\" role=\"img\" aria-label=\"" + xml_escape(title_) +
         "\">" + body_ + "</svg>";
}

std::string diverging_colour(double value) {
  const double v = std::isfinite(value) ? std::clamp(value, -1.0, 1.0) : 0.0;
  // White to red (#c0392b-ish) for positive, white to blue for negative.
  const double a = std::abs(v);
  const int r = v >= 0 ? 255 - static_cast<int>(a * (255 - 192)) : 255 - static_cast<int>(a * 215);
  const int g = v >= 0 ? 255 - static_cast<int>(a * (255 - 57)) : 255 - static_cast<int>(a * 140);
  const int b = v >= 0 ? 255 - static_cast<int>(a * (255 - 43)) : 255 - static_cast<int>(a * 75);
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
  return buf;
}

}  // namespace kincal::report
