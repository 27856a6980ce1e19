// SPDX-License-Identifier: Apache-2.0
#pragma once
// A small SVG plotting component for the report: a data rectangle mapped onto a pixel box with
// axes, ticks, clipping, markers and a legend; the output is XML-clean text (escaped, every
// element closed) so a page that inlines it stays well-formed.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>

namespace wallcal::outputs {

// Escapes text and attribute values for XML/HTML.
inline std::string Esc(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default:
        // Control characters are not allowed in XML 1.0 text.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') {
          out += ' ';
        } else {
          out += c;
        }
    }
  }
  return out;
}

// One plot: a data rectangle mapped onto a pixel box with margins for the axes. Everything drawn
// with data coordinates is clipped to the box. Pixel coordinates are printed with one decimal,
// which keeps a plot of a few thousand points at a few hundred kilobytes.
// The marker shapes a plot draws (Marker) and shows in its legend.
enum class Shape { kPlus, kCross, kTriangle, kSquare, kRing };
// A legend line's swatch: a dot, a solid or dashed line, or one of the plot's markers.
enum class Swatch { kDot, kLine, kDash, kPlus, kCross, kTriangle, kSquare, kRing };

class SvgPlot {
 public:
  SvgPlot(int width_px, int height_px, int* clip_counter)
      : width_(width_px), height_(height_px), clip_id_("clip" + std::to_string((*clip_counter)++)) {}

  // Data range; with equal_aspect the smaller span grows (about its centre) so that a metre is
  // the same length on both axes.
  void SetRange(double x0, double x1, double y0, double y1, bool equal_aspect) {
    if (!(x1 > x0)) { x0 -= 0.5; x1 += 0.5; }
    if (!(y1 > y0)) { y0 -= 0.5; y1 += 0.5; }
    if (equal_aspect) {
      const double sx = (x1 - x0) / BoxW(), sy = (y1 - y0) / BoxH();
      const double s = std::max(sx, sy);
      const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
      x0 = cx - 0.5 * s * BoxW();
      x1 = cx + 0.5 * s * BoxW();
      y0 = cy - 0.5 * s * BoxH();
      y1 = cy + 0.5 * s * BoxH();
    }
    x0_ = x0; x1_ = x1; y0_ = y0; y1_ = y1;
  }

  double Px(double x) const { return kLeft + (x - x0_) / (x1_ - x0_) * BoxW(); }
  double Py(double y) const { return kTop + (y1_ - y) / (y1_ - y0_) * BoxH(); }
  double PixelsPerUnitX() const { return BoxW() / (x1_ - x0_); }
  bool Inside(double x, double y) const { return x >= x0_ && x <= x1_ && y >= y0_ && y <= y1_; }

  // Frame, grid, ticks and axis labels (units in the labels).
  void Axes(const std::string& x_label, const std::string& y_label) {
    std::ostringstream& o = axes_;
    const double xs = NiceStep(x1_ - x0_, BoxW() / 90.0), ys = NiceStep(y1_ - y0_, BoxH() / 55.0);
    for (double v = std::ceil(x0_ / xs) * xs; v <= x1_ + 1e-9 * xs; v += xs) {
      const double p = Px(v);
      o << "<line x1=\"" << P(p) << "\" y1=\"" << P(kTop) << "\" x2=\"" << P(p) << "\" y2=\""
        << P(kTop + BoxH()) << "\" stroke=\"#e4e4e4\" stroke-width=\"1\"/>";
      o << "<text x=\"" << P(p) << "\" y=\"" << P(kTop + BoxH() + 14) << "\" text-anchor=\"middle\">"
        << TickLabel(v, xs) << "</text>";
    }
    for (double v = std::ceil(y0_ / ys) * ys; v <= y1_ + 1e-9 * ys; v += ys) {
      const double p = Py(v);
      o << "<line x1=\"" << P(kLeft) << "\" y1=\"" << P(p) << "\" x2=\"" << P(kLeft + BoxW())
        << "\" y2=\"" << P(p) << "\" stroke=\"#e4e4e4\" stroke-width=\"1\"/>";
      o << "<text x=\"" << P(kLeft - 5) << "\" y=\"" << P(p + 4) << "\" text-anchor=\"end\">"
        << TickLabel(v, ys) << "</text>";
    }
    o << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << P(BoxW()) << "\" height=\""
      << P(BoxH()) << "\" fill=\"none\" stroke=\"#444\" stroke-width=\"1\"/>";
    o << "<text x=\"" << P(kLeft + BoxW() / 2) << "\" y=\"" << height_ - 6
      << "\" text-anchor=\"middle\" class=\"label\">" << Esc(x_label) << "</text>";
    o << "<text transform=\"translate(14," << P(kTop + BoxH() / 2)
      << ") rotate(-90)\" text-anchor=\"middle\" class=\"label\">" << Esc(y_label) << "</text>";
  }

  // Drawing in data coordinates (clipped).
  void Line(double xa, double ya, double xb, double yb, const std::string& stroke, double width,
            const std::string& dash = "", double opacity = 1.0) {
    data_ << "<line x1=\"" << P(Px(xa)) << "\" y1=\"" << P(Py(ya)) << "\" x2=\"" << P(Px(xb))
          << "\" y2=\"" << P(Py(yb)) << "\" stroke=\"" << stroke << "\" stroke-width=\"" << width
          << "\"" << Dash(dash);
    if (opacity < 1.0) data_ << " stroke-opacity=\"" << opacity << "\"";
    data_ << "/>";
  }
  void Polyline(const std::vector<Eigen::Vector2d>& points, const std::string& stroke, double width,
                const std::string& dash = "", const std::string& fill = "none") {
    if (points.size() < 2) return;
    data_ << "<polyline fill=\"" << fill << "\" stroke=\"" << stroke << "\" stroke-width=\""
          << width << "\"" << Dash(dash) << " points=\"";
    // A vertex less than half a pixel from the last one drawn changes nothing visible: skipped
    // (the last vertex is always drawn), so a long track costs its drawn length, not its fixes.
    double last_x = 0, last_y = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      const double px = Px(points[i].x()), py = Py(points[i].y());
      if (i > 0 && i + 1 < points.size() && std::hypot(px - last_x, py - last_y) < 0.5) continue;
      data_ << (i ? " " : "") << P(px) << "," << P(py);
      last_x = px;
      last_y = py;
    }
    data_ << "\"/>";
  }
  void Dot(double x, double y, double r_px, const std::string& fill,
           const std::string& stroke = "none") {
    data_ << "<circle cx=\"" << P(Px(x)) << "\" cy=\"" << P(Py(y)) << "\" r=\"" << r_px
          << "\" fill=\"" << fill << "\" stroke=\"" << stroke << "\"/>";
  }
  // Many dots of one colour, as one path of zero-length round-capped strokes at whole pixels,
  // sorted and written as relative moves (about 8 bytes a dot instead of 70 for a <circle>).
  // Dots at the same pixel are drawn once (a dot covers several pixels: nothing visible is
  // lost). With cell_px > 1, of the dots whose centres fall in the same cell_px × cell_px cell
  // only the first is drawn: with cells no wider than a dot the cloud looks the same, and its
  // size is bounded by the plot's area instead of the number of points. Returns the number drawn.
  size_t DotCloud(const std::vector<Eigen::Vector2d>& points, double r_px, const std::string& color,
                  double cell_px) {
    const double cell = std::max(1.0, cell_px);
    std::unordered_set<long long> taken;
    std::vector<std::pair<long long, long long>> pixels;
    for (const Eigen::Vector2d& p : points) {
      const double px = Px(p.x()), py = Py(p.y());
      if (!std::isfinite(px) || !std::isfinite(py)) continue;
      const long long ix = std::llround(px), iy = std::llround(py);
      const long long cx = static_cast<long long>(std::floor(static_cast<double>(ix) / cell));
      const long long cy = static_cast<long long>(std::floor(static_cast<double>(iy) / cell));
      if (taken.insert(cx * 1000003LL + cy).second) pixels.emplace_back(ix, iy);
    }
    if (pixels.empty()) return 0;
    std::sort(pixels.begin(), pixels.end());
    data_ << "<path d=\"M" << pixels[0].first << ' ' << pixels[0].second << "h0";
    for (size_t i = 1; i < pixels.size(); ++i) {
      const long long dx = pixels[i].first - pixels[i - 1].first;
      const long long dy = pixels[i].second - pixels[i - 1].second;
      data_ << 'm' << dx << (dy < 0 ? "" : " ") << dy << "h0";
    }
    data_ << "\" fill=\"none\" stroke=\"" << color << "\" stroke-width=\"" << 2.0 * r_px
          << "\" stroke-linecap=\"round\"/>";
    return pixels.size();
  }
  void Marker(double x, double y, Shape shape, double size_px,
              const std::string& color) {
    MarkerPx(data_, Px(x), Py(y), shape, size_px, color);
  }
  // Axis-aligned rectangle from data corners.
  void Rect(double xa, double ya, double xb, double yb, const std::string& fill,
            const std::string& stroke = "none", const std::string& dash = "") {
    const double pa = Px(std::min(xa, xb)), pb = Px(std::max(xa, xb));
    const double qa = Py(std::max(ya, yb)), qb = Py(std::min(ya, yb));
    data_ << "<rect x=\"" << P(pa) << "\" y=\"" << P(qa) << "\" width=\"" << P(pb - pa)
          << "\" height=\"" << P(qb - qa) << "\" fill=\"" << fill << "\" stroke=\"" << stroke
          << "\"" << Dash(dash) << "/>";
  }
  void Text(double x, double y, const std::string& text, const std::string& color = "#222",
            const std::string& anchor = "start", double dx_px = 0, double dy_px = 0) {
    data_ << "<text x=\"" << P(Px(x) + dx_px) << "\" y=\"" << P(Py(y) + dy_px)
          << "\" text-anchor=\"" << anchor << "\" fill=\"" << color << "\">" << Esc(text)
          << "</text>";
  }
  // A legend line in the top-left corner of the box (pixel placement, not clipped).
  void Legend(const std::string& swatch_svg_color, Swatch swatch, const std::string& text) {
    const double x = kLeft + 8, y = kTop + 14 + 15 * legend_rows_++;
    if (swatch == Swatch::kLine) {
      over_ << "<line x1=\"" << P(x) << "\" y1=\"" << P(y - 4) << "\" x2=\"" << P(x + 14)
            << "\" y2=\"" << P(y - 4) << "\" stroke=\"" << swatch_svg_color
            << "\" stroke-width=\"2.5\"/>";
    } else if (swatch == Swatch::kDash) {
      over_ << "<line x1=\"" << P(x) << "\" y1=\"" << P(y - 4) << "\" x2=\"" << P(x + 14)
            << "\" y2=\"" << P(y - 4) << "\" stroke=\"" << swatch_svg_color
            << "\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>";
    } else if (swatch != Swatch::kDot) {
      // The same marker the plot draws: the marker swatches follow Shape's order.
      const Shape shape = static_cast<Shape>(static_cast<int>(swatch) -
                                             static_cast<int>(Swatch::kPlus));
      MarkerPx(over_, x + 7, y - 4, shape, 4.5, swatch_svg_color);
    } else {
      over_ << "<circle cx=\"" << P(x + 7) << "\" cy=\"" << P(y - 4) << "\" r=\"3.5\" fill=\""
            << swatch_svg_color << "\"/>";
    }
    over_ << "<text x=\"" << P(x + 20) << "\" y=\"" << P(y) << "\" class=\"legend\">" << Esc(text)
          << "</text>";
    legend_width_ = std::max(legend_width_, 26.0 + 6.3 * static_cast<double>(text.size()));
  }
  // Free text in pixel coordinates (not clipped).
  void Note(double x_px, double y_px, const std::string& text, const std::string& anchor = "start") {
    over_ << "<text x=\"" << P(x_px) << "\" y=\"" << P(y_px) << "\" text-anchor=\"" << anchor
          << "\" class=\"legend\">" << Esc(text) << "</text>";
  }
  void Raw(const std::string& svg_data) { data_ << svg_data; }

  // A marker centred at pixel (px, py), `s` pixels from centre to edge.
  static void MarkerPx(std::ostringstream& out, double px, double py, Shape shape, double s,
                       const std::string& color) {
    if (shape == Shape::kPlus || shape == Shape::kCross) {
      const double a = shape == Shape::kPlus ? 0.0 : 0.7071;
      const double b = shape == Shape::kPlus ? 1.0 : 0.7071;
      out << "<path d=\"M" << P(px - s * b) << "," << P(py - s * a) << "L" << P(px + s * b)
          << "," << P(py + s * a) << "M" << P(px + s * a) << "," << P(py - s * b) << "L"
          << P(px - s * a) << "," << P(py + s * b) << "\" stroke=\"" << color
          << "\" stroke-width=\"2\" fill=\"none\"/>";
    } else if (shape == Shape::kTriangle) {
      out << "<polygon points=\"" << P(px) << "," << P(py - s) << " " << P(px - s) << ","
          << P(py + s * 0.8) << " " << P(px + s) << "," << P(py + s * 0.8) << "\" fill=\"none\""
          << " stroke=\"" << color << "\" stroke-width=\"1.5\"/>";
    } else if (shape == Shape::kSquare) {
      out << "<rect x=\"" << P(px - s) << "\" y=\"" << P(py - s) << "\" width=\"" << P(2 * s)
          << "\" height=\"" << P(2 * s) << "\" fill=\"" << color << "\"/>";
    } else {  // ring
      out << "<circle cx=\"" << P(px) << "\" cy=\"" << P(py) << "\" r=\"" << s
          << "\" fill=\"none\" stroke=\"" << color << "\" stroke-width=\"1.5\"/>";
    }
  }

  std::string Svg(const std::string& title) const {
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_ << "\" height=\"" << height_
      << "\" viewBox=\"0 0 " << width_ << " " << height_ << "\" class=\"plot\">";
    o << "<title>" << Esc(title) << "</title>";
    o << "<defs><clipPath id=\"" << clip_id_ << "\"><rect x=\"" << kLeft << "\" y=\"" << kTop
      << "\" width=\"" << P(BoxW()) << "\" height=\"" << P(BoxH()) << "\"/></clipPath></defs>";
    o << "<rect x=\"0\" y=\"0\" width=\"" << width_ << "\" height=\"" << height_
      << "\" fill=\"#fff\"/>";
    o << "<text x=\"" << kLeft << "\" y=\"17\" class=\"ptitle\">" << Esc(title) << "</text>";
    o << axes_.str();
    o << "<g clip-path=\"url(#" << clip_id_ << ")\">" << data_.str() << "</g>";
    if (legend_rows_ > 0) {
      o << "<rect x=\"" << kLeft + 3 << "\" y=\"" << kTop + 3 << "\" width=\"" << P(legend_width_)
        << "\" height=\"" << 15 * legend_rows_ + 6 << "\" fill=\"#fff\" fill-opacity=\"0.85\""
        << " stroke=\"#bbb\"/>";
    }
    o << over_.str();
    o << "</svg>";
    return o.str();
  }

  static constexpr double kLeft = 62, kRight = 14, kTop = 26, kBottom = 40;
  double BoxW() const { return width_ - kLeft - kRight; }
  double BoxH() const { return height_ - kTop - kBottom; }

  static std::string P(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.1f", v);
    return buffer;
  }

 private:
  static std::string Dash(const std::string& dash) {
    return dash.empty() ? std::string() : " stroke-dasharray=\"" + dash + "\"";
  }
  static double NiceStep(double span, double target_ticks) {
    const double raw = span / std::max(1.0, target_ticks);
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    const double m = raw / magnitude;
    const double nice = m < 1.5 ? 1.0 : m < 3.0 ? 2.0 : m < 7.0 ? 5.0 : 10.0;
    return nice * magnitude;
  }
  static std::string TickLabel(double v, double step) {
    const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
    if (std::fabs(v) < 0.5 * step * 1e-6) v = 0.0;
    char buffer[48];
    std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, v);
    std::string s = buffer;
    if (s[0] == '-') s = "\xe2\x88\x92" + s.substr(1);  // U+2212 minus sign
    return s;
  }

  int width_, height_;
  std::string clip_id_;
  double x0_ = 0, x1_ = 1, y0_ = 0, y1_ = 1;
  std::ostringstream axes_, data_, over_;
  int legend_rows_ = 0;
  double legend_width_ = 0;
};

// Bounds of a set of points.
struct Box {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  void Add(double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x); x1 = std::max(x1, x);
    y0 = std::min(y0, y); y1 = std::max(y1, y);
  }
  void Add(const Eigen::Vector2d& p) { Add(p.x(), p.y()); }
  bool Empty() const { return x0 > x1; }
  void Pad(double fraction, double min_pad) {
    const double px = std::max(min_pad, fraction * (x1 - x0));
    const double py = std::max(min_pad, fraction * (y1 - y0));
    x0 -= px; x1 += px; y0 -= py; y1 += py;
  }
};


}  // namespace wallcal::outputs
