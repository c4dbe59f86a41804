#pragma once
// A small SVG plotting helper for reports a person reads (framework/report: the pages for people):
// charts drawn as inline SVG, no script, every text escaped. A chart has a plot area with linear or
// logarithmic axes; callers draw points, lines, rectangles and text in data coordinates and
// get one <svg> element back. Tooltips are SVG <title> children (shown on hover, no script).

#include <string>
#include <string_view>
#include <vector>

namespace kincal::report {

/// Text made safe for XML/HTML content and attribute values (& < > " ').
std::string xml_escape(std::string_view text);

/// A number as a person would read it: %.*g with `digits` significant digits, "–" when not
/// finite.
std::string format_number(double value, int digits = 4);

/// Tick values for an axis from lo to hi: about `count` "nice" values (1, 2, 5 x 10^k).
std::vector<double> nice_ticks(double lo, double hi, int count = 5);

struct Axis {
  double lo = 0, hi = 1;
  bool log = false;  ///< logarithmic (lo and hi > 0)
  std::string label;
};

class SvgChart {
 public:
  /// A chart of `width` x `height` pixels; `margin_left` leaves room for long tick or
  /// category labels.
  SvgChart(int width, int height, std::string title, int margin_left = 70);

  void set_x(Axis axis) { x_ = std::move(axis); }
  void set_y(Axis axis) { y_ = std::move(axis); }
  const Axis& x() const { return x_; }
  const Axis& y() const { return y_; }

  /// Pixel coordinates of data coordinates (clamped to the axis range for log <= 0).
  double px(double x) const;
  double py(double y) const;

  /// Frame, ticks, tick labels, axis labels and the title. `x_ticks` false: the caller
  /// labels the x axis (categories).
  void draw_axes(bool x_ticks = true, bool y_ticks = true);

  /// Shapes in data coordinates; `css_class` styles them (the page's <style>), `tooltip`
  /// becomes a <title> child.
  void point(double x, double y, double radius, const std::string& css_class,
             const std::string& tooltip = "");
  void line(double x0, double y0, double x1, double y1, const std::string& css_class);
  void rect(double x0, double y0, double x1, double y1, const std::string& css_class,
            const std::string& tooltip = "");
  void polyline(const std::vector<std::pair<double, double>>& points, const std::string& css_class);
  /// Text at data coordinates; anchor "start", "middle" or "end".
  void text(double x, double y, const std::string& text, const std::string& css_class,
            const std::string& anchor = "start");
  /// Text at pixel coordinates (labels outside the plot area), optionally rotated.
  void text_px(double x, double y, const std::string& text, const std::string& css_class,
               const std::string& anchor = "start", double rotate_deg = 0);
  /// A filled rectangle in pixel coordinates with an inline fill colour (heat maps).
  void cell_px(double x, double y, double w, double h, const std::string& fill,
               const std::string& tooltip = "");

  int width() const { return width_; }
  int height() const { return height_; }
  /// Plot area in pixels.
  double left() const { return margin_left_; }
  double right() const { return width_ - kMarginRight; }
  double top() const { return kMarginTop; }
  double bottom() const { return height_ - kMarginBottom; }

  /// The finished <svg> element.
  std::string str() const;

  static constexpr int kMarginRight = 20, kMarginTop = 28, kMarginBottom = 46;

 private:
  double to_unit(const Axis& a, double v) const;

  int width_, height_, margin_left_;
  std::string title_;
  Axis x_, y_;
  std::string body_;
};

/// A diverging colour for a value in [-1, 1]: blue (-1), white (0), red (+1), as "#rrggbb".
std::string diverging_colour(double value);

}  // namespace kincal::report
