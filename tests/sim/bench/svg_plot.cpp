#include "svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

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

}  // namespace

std::string log_log_svg(const std::vector<Series>& series, const PlotLabels& labels, int width,
                        int height) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = 0;
  double y_lo = std::numeric_limits<double>::infinity(), y_hi = 0;
  for (const auto& s : series) {
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!(s.x[i] > 0 && s.y[i] > 0) || !std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_lo = std::min(x_lo, s.x[i]);
      x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]);
      y_hi = std::max(y_hi, s.y[i]);
    }
  }
  if (!(x_hi > 0)) x_lo = 1, x_hi = 10, y_lo = 1, y_hi = 10;
  // Whole decades around the data.
  const double lx0 = std::floor(std::log10(x_lo)),
               lx1 = std::max(lx0 + 1, std::ceil(std::log10(x_hi)));
  const double ly0 = std::floor(std::log10(y_lo)),
               ly1 = std::max(ly0 + 1, std::ceil(std::log10(y_hi)));
  const double left = 90, right = 230, top = 50, bottom = 70;
  const double pw = width - left - right, ph = height - top - bottom;
  auto px = [&](double x) { return left + (std::log10(x) - lx0) / (lx1 - lx0) * pw; };
  auto py = [&](double y) { return top + (ly1 - std::log10(y)) / (ly1 - ly0) * ph; };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" font-family=\"sans-serif\" font-size=\"13\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << width / 2 << "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">"
      << escape(labels.title) << "</text>\n";
  for (double d = lx0; d <= lx1 + 1e-9; ++d) {
    const double x = left + (d - lx0) / (lx1 - lx0) * pw;
    svg << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + ph
        << "\" stroke=\"#ddd\"/>\n<text x=\"" << x << "\" y=\"" << top + ph + 18
        << "\" text-anchor=\"middle\">1e" << static_cast<int>(d) << "</text>\n";
  }
  for (double d = ly0; d <= ly1 + 1e-9; ++d) {
    const double y = top + (ly1 - d) / (ly1 - ly0) * ph;
    svg << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + pw << "\" y2=\"" << y
        << "\" stroke=\"#ddd\"/>\n<text x=\"" << left - 8 << "\" y=\"" << y + 4
        << "\" text-anchor=\"end\">1e" << static_cast<int>(d) << "</text>\n";
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
      if (!(s.x[i] > 0 && s.y[i] > 0) || !std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
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

}  // namespace incise::bench
