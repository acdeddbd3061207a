#pragma once
// Small line plots as SVG (log-log for the accuracy benchmark's "error against time" figure,
// linear for timelines): one polyline with markers per series, grid lines, axis labels and a
// legend. Plain text out, no dependencies.
#include <string>
#include <vector>

namespace incise::bench {

struct Series {
  std::string name;
  std::vector<double> x;  // > 0 (log axis); points with x <= 0 or y <= 0 are left out
  std::vector<double> y;  // > 0
};

struct PlotLabels {
  std::string title;
  std::string x_axis;
  std::string y_axis;
};

// The SVG document (width x height pixels).
std::string log_log_svg(const std::vector<Series>& series, const PlotLabels& labels,
                        int width = 900, int height = 600);

// The same with linear axes from 0 (or below, for negative data) to a rounded maximum.
std::string linear_svg(const std::vector<Series>& series, const PlotLabels& labels, int width = 900,
                       int height = 600);

}  // namespace incise::bench
