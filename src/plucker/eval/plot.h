// A small, dependency-free SVG plotter for trajectory evaluation figures.
//
// One figure, two panels:
//   left   top view of the ground truth and the (aligned) estimate in the plane of the two axes
//          of largest extent (or a chosen plane), EQUAL scale on both axes, metres, start (circle)
//          and end (square) markers, a legend;
//   right  an error along the trajectory (ATE per pose, RPE per pair, KITTI per segment) against
//          the distance travelled, one or more series, or a message when there is nothing to
//          plot (e.g. "no segment").
// The output is a complete standalone SVG document (a string; the caller writes it). No file I/O.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace plucker {
namespace eval {

enum class PlotPlane { kAuto, kXY, kXZ, kYZ };

// std::nullopt-free parse: returns false for an unknown name ("auto", "xy", "xz", "yz").
bool ParsePlotPlane(const std::string& name, PlotPlane* plane);

struct PlotSeries {
  std::string label;
  std::vector<Eigen::Vector2d> points;  // (x, y) in data units; non-finite points are skipped
  std::string color = "#1f77b4";
  bool line = true;      // connect the points
  bool markers = false;  // draw a dot at each point
};

struct TrajectoryPlot {
  std::string title;     // e.g. "ATE (se3 aligned): RMSE 0.412 m over 4541 poses"
  std::string subtitle;  // e.g. the file names
  std::vector<Eigen::Vector3d> positions_gt;
  std::vector<Eigen::Vector3d> positions_est;
  std::string label_gt = "ground truth";
  std::string label_est = "estimate";
  PlotPlane plane = PlotPlane::kAuto;

  std::string error_title;  // title of the right panel
  std::string error_x_label = "distance travelled [m]";
  std::string error_y_label;  // e.g. "position error [m]"
  std::vector<PlotSeries> error_series;
  std::string error_message;  // shown in the right panel when error_series is empty

  int width = 1280;  // pixels
  int height = 640;
};

// A panel of series against a common x (time, distance), as the right panel above.
struct SeriesPanel {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  std::string message;     // shown when no series has a point
  bool zero_line = false;  // the y range includes 0 (errors)
};

// Panels in a grid of `columns`, row by row, under a title.
struct SeriesFigure {
  std::string title, subtitle;
  std::vector<SeriesPanel> panels;
  int columns = 3;
  int width = 1280;        // pixels
  int panel_height = 320;  // pixels per row
};

std::string RenderSeriesFigureSvg(const SeriesFigure& figure);

// Documents of this plotter (RenderTrajectoryPlotSvg, RenderSeriesFigureSvg) one below the other
// in one SVG document. Throws std::invalid_argument for other text.
std::string StackSvgDocuments(const std::vector<std::string>& documents);

// The two coordinate indices (0 x, 1 y, 2 z) drawn horizontally and vertically. kAuto drops the
// axis of smallest extent of `positions` (x-z for a KITTI cam0 trajectory, x-y for most others).
std::pair<int, int> PlotAxes(const std::vector<Eigen::Vector3d>& positions, PlotPlane plane);

// About `target` round tick values (steps 1, 2 or 5 times a power of ten) covering [lo, hi].
std::vector<double> NiceTicks(double lo, double hi, int target);

std::string RenderTrajectoryPlotSvg(const TrajectoryPlot& plot);

}  // namespace eval
}  // namespace plucker
