#include "svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace incise::bench {
namespace {

// Colour-blind-safe palette (Okabe-Ito), cycled.
constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                    "#E69F00", "#56B4E9", "#000000", "#F0E442"};
constexpr const char* kDashes[] = {"none", "7,4", "2,3", "9,3,2,3"};

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

// One axis: the data range rounded out, grid values, and the map to [0, 1].
struct Axis {
  bool log = false;
  double lo = 0, hi = 1;  // decades (log10) for a log axis
  std::vector<double> ticks;

  double unit(double v) const { return ((log ? std::log10(v) : v) - lo) / (hi - lo); }
  std::string label(double tick) const {
    return log ? "1e" + std::to_string(static_cast<int>(tick)) : number(tick);
  }
  bool shows(double v) const { return std::isfinite(v) && (!log || v > 0); }
};

Axis make_axis(bool log, double data_lo, double data_hi) {
  Axis axis;
  axis.log = log;
  if (log) {
    if (!(data_hi > 0)) data_lo = 1, data_hi = 10;
    // Whole decades around the data.
    axis.lo = std::floor(std::log10(data_lo));
    axis.hi = std::max(axis.lo + 1, std::ceil(std::log10(data_hi)));
    for (double d = axis.lo; d <= axis.hi + 1e-9; ++d)
      axis.ticks.push_back(d);
    return axis;
  }
  if (!(data_hi >= data_lo)) data_lo = 0, data_hi = 1;
  data_lo = std::min(0.0, data_lo);
  if (data_hi <= data_lo) data_hi = data_lo + 1;
  // A step of 1, 2 or 5 times a power of ten giving at most 8 intervals.
  const double raw = (data_hi - data_lo) / 8;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = decade;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * decade;
    if (step >= raw) break;
  }
  axis.lo = std::floor(data_lo / step) * step;
  axis.hi = std::ceil(data_hi / step) * step;
  for (double t = axis.lo; t <= axis.hi + 1e-9 * step; t += step)
    axis.ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return axis;
}

std::string line_svg(const std::vector<Series>& series, const PlotLabels& labels, bool log,
                     int width, int height) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  double y_lo = x_lo, y_hi = -x_lo;
  for (const auto& s : series) {
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (log && !(s.x[i] > 0 && s.y[i] > 0)) continue;
      x_lo = std::min(x_lo, s.x[i]);
      x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]);
      y_hi = std::max(y_hi, s.y[i]);
    }
  }
  const Axis ax = make_axis(log, x_lo, x_hi), ay = make_axis(log, y_lo, y_hi);
  const double left = 90, right = 230, top = 50, bottom = 70;
  const double pw = width - left - right, ph = height - top - bottom;
  auto px = [&](double x) { return left + ax.unit(x) * pw; };
  auto py = [&](double y) { return top + (1 - ay.unit(y)) * ph; };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" font-family=\"sans-serif\" font-size=\"13\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << width / 2 << "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">"
      << escape(labels.title) << "</text>\n";
  for (const double tick : ax.ticks) {
    const double x = left + (tick - ax.lo) / (ax.hi - ax.lo) * pw;
    svg << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + ph
        << "\" stroke=\"#ddd\"/>\n<text x=\"" << x << "\" y=\"" << top + ph + 18
        << "\" text-anchor=\"middle\">" << ax.label(tick) << "</text>\n";
  }
  for (const double tick : ay.ticks) {
    const double y = top + (ay.hi - tick) / (ay.hi - ay.lo) * ph;
    svg << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + pw << "\" y2=\"" << y
        << "\" stroke=\"#ddd\"/>\n<text x=\"" << left - 8 << "\" y=\"" << y + 4
        << "\" text-anchor=\"end\">" << ay.label(tick) << "</text>\n";
  }
  svg << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"#333\"/>\n"
      << "<text x=\"" << left + pw / 2 << "\" y=\"" << height - 20 << "\" text-anchor=\"middle\">"
      << escape(labels.x_axis) << "</text>\n"
      << "<text transform=\"translate(24," << top + ph / 2
      << ") rotate(-90)\" text-anchor=\"middle\">" << escape(labels.y_axis) << "</text>\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto& s = series[k];
    const char* colour = kColours[k % std::size(kColours)];
    // Past the palette, the colours repeat with another dash pattern.
    const char* dash = kDashes[(k / std::size(kColours)) % std::size(kDashes)];
    std::ostringstream points;
    std::ostringstream markers;
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!ax.shows(s.x[i]) || !ay.shows(s.y[i])) continue;
      points << number(px(s.x[i])) << "," << number(py(s.y[i])) << " ";
      markers << "<circle cx=\"" << number(px(s.x[i])) << "\" cy=\"" << number(py(s.y[i]))
              << "\" r=\"3.5\" fill=\"" << colour << "\"/>\n";
    }
    svg << "<polyline fill=\"none\" stroke=\"" << colour
        << "\" stroke-width=\"2\" stroke-dasharray=\"" << dash << "\" points=\"" << points.str()
        << "\"/>\n"
        << markers.str();
    const double ly = top + 10 + 20 * static_cast<double>(k);
    svg << "<line x1=\"" << left + pw + 15 << "\" y1=\"" << ly << "\" x2=\"" << left + pw + 40
        << "\" y2=\"" << ly << "\" stroke=\"" << colour
        << "\" stroke-width=\"2\" stroke-dasharray=\"" << dash << "\"/>\n"
        << "<text x=\"" << left + pw + 46 << "\" y=\"" << ly + 4 << "\">" << escape(s.name)
        << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace

std::string log_log_svg(const std::vector<Series>& series, const PlotLabels& labels, int width,
                        int height) {
  return line_svg(series, labels, true, width, height);
}

std::string linear_svg(const std::vector<Series>& series, const PlotLabels& labels, int width,
                       int height) {
  return line_svg(series, labels, false, width, height);
}

}  // namespace incise::bench
