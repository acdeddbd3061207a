#pragma once
// A small log-log line plot as SVG, for the accuracy benchmark's "error against time" figure: one
// polyline with markers per series, decade grid lines, axis labels and a legend. Plain text out,
// no dependencies.
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

}  // namespace incise::bench
