#include "plucker/eval/plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "plucker/eval/alignment.h"
#include "plucker/eval/eval_test_utils.h"

namespace plucker {
namespace eval {
namespace {

int Count(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

TEST(Plot, AutoPlaneDropsTheSmallestExtent) {
  // KITTI cam0: x right, y down (small extent), z forward.
  EXPECT_EQ(PlotAxes(Positions(testing::Curve(200)), PlotPlane::kAuto), std::make_pair(0, 2));
  std::vector<Eigen::Vector3d> planar_xy = {{0, 0, 0}, {10, 5, 0.1}, {20, -3, 0.2}};
  EXPECT_EQ(PlotAxes(planar_xy, PlotPlane::kAuto), std::make_pair(0, 1));
  EXPECT_EQ(PlotAxes(planar_xy, PlotPlane::kYZ), std::make_pair(1, 2));
  EXPECT_EQ(PlotAxes({}, PlotPlane::kAuto), std::make_pair(0, 1));
}

TEST(Plot, NiceTicksAreRoundAndCoverTheRange) {
  EXPECT_EQ(NiceTicks(0, 100, 5), (std::vector<double>{0, 20, 40, 60, 80, 100}));
  const std::vector<double> t = NiceTicks(-0.013, 0.027, 4);
  ASSERT_FALSE(t.empty());
  EXPECT_GE(t.front(), -0.013);
  EXPECT_LE(t.back(), 0.027);
  EXPECT_NEAR(t[1] - t[0], 0.01, 1e-15);
  EXPECT_FALSE(NiceTicks(3, 3, 5).empty());
  EXPECT_TRUE(NiceTicks(0, std::nan(""), 5).empty());
}

TrajectoryPlot SomePlot() {
  TrajectoryPlot plot;
  plot.title = "ATE <se3> & more";
  plot.positions_gt = Positions(testing::Curve(100));
  plot.positions_est = plot.positions_gt;
  for (auto& p : plot.positions_est) p.x() += 0.3;
  plot.error_title = "Position error per pose";
  plot.error_y_label = "position error [m]";
  PlotSeries s;
  s.label = "ATE";
  for (int i = 0; i < 100; ++i) s.points.emplace_back(i, 0.3);
  plot.error_series.push_back(s);
  return plot;
}

TEST(Plot, SvgHasBothPanelsLegendMarkersAndEscapedText) {
  const std::string svg = RenderTrajectoryPlotSvg(SomePlot());
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("ATE &lt;se3&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(svg.find("<se3>"), std::string::npos);
  EXPECT_NE(svg.find("x-z plane"), std::string::npos);
  EXPECT_NE(svg.find("x [m]"), std::string::npos);
  EXPECT_NE(svg.find("z [m]"), std::string::npos);
  EXPECT_NE(svg.find("ground truth"), std::string::npos);
  EXPECT_NE(svg.find("position error [m]"), std::string::npos);
  EXPECT_EQ(Count(svg, "<polyline"), 3);  // gt, estimate, error series
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(Count(svg, "<svg"), 1);
  EXPECT_EQ(Count(svg, "<defs>"), Count(svg, "</defs>"));
}

TEST(Plot, EmptyErrorPanelShowsTheMessage) {
  TrajectoryPlot plot = SomePlot();
  plot.error_series.clear();
  plot.error_message =
      "no segment: path 13 m, a long message that must wrap onto more lines "
      "than one so that it stays inside the panel of the figure";
  const std::string svg = RenderTrajectoryPlotSvg(plot);
  EXPECT_NE(svg.find("no segment: path 13 m"), std::string::npos);
  EXPECT_GE(Count(svg, "fill=\"#aa3333\""), 2);  // wrapped
  EXPECT_EQ(Count(svg, "<polyline"), 2);
}

TEST(Plot, DegenerateInputStillRendersWithoutNaN) {
  TrajectoryPlot plot;
  plot.positions_gt = {Eigen::Vector3d(1, 1, 1)};
  plot.positions_est = {Eigen::Vector3d(1, 1, 1)};
  PlotSeries s;
  s.points = {{0, 0}, {std::nan(""), 1}};
  plot.error_series.push_back(s);
  const std::string svg = RenderTrajectoryPlotSvg(plot);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST(Plot, SeriesFigureHasEveryPanelAndItsSeries) {
  SeriesFigure figure;
  figure.title = "biases <est> & gt";
  for (int p = 0; p < 4; ++p) {
    SeriesPanel panel;
    panel.title = "panel " + std::to_string(p);
    panel.y_label = "unit " + std::to_string(p);
    for (int k = 0; k < 2; ++k) {
      PlotSeries series;
      series.label = "series " + std::to_string(k);
      for (int i = 0; i < 50; ++i) series.points.emplace_back(i, std::sin(0.1 * i + p + k));
      panel.series.push_back(series);
    }
    figure.panels.push_back(panel);
  }
  SeriesPanel empty;
  empty.title = "empty";
  empty.message = "no ground truth biases";
  figure.panels.push_back(empty);
  const std::string svg = RenderSeriesFigureSvg(figure);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("biases &lt;est&gt; &amp; gt"), std::string::npos);
  EXPECT_EQ(Count(svg, "<polyline"), 8);
  for (int p = 0; p < 4; ++p) EXPECT_NE(svg.find("unit " + std::to_string(p)), std::string::npos);
  EXPECT_NE(svg.find("no ground truth biases"), std::string::npos);
  EXPECT_EQ(Count(svg, "<clipPath"), 5);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  // Two rows of three: 70 + 2 * 320 pixels high.
  EXPECT_NE(svg.find("height=\"710\""), std::string::npos);
}

TEST(Plot, StackedDocumentsAreOneSvgAsHighAsBoth) {
  const std::string a = RenderTrajectoryPlotSvg(SomePlot());
  SeriesFigure figure;
  figure.panels.resize(2);
  const std::string b = RenderSeriesFigureSvg(figure);
  const std::string svg = StackSvgDocuments({a, b});
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_EQ(Count(svg, "<?xml"), 1);
  EXPECT_EQ(Count(svg, "<svg"), 3);
  EXPECT_EQ(Count(svg, "</svg>"), 3);
  EXPECT_NE(svg.find("height=\"1030\""), std::string::npos);  // 640 + 390
  EXPECT_NE(svg.find("translate(0,640"), std::string::npos);
  EXPECT_THROW(StackSvgDocuments({"<html/>"}), std::invalid_argument);
}

}  // namespace
}  // namespace eval
}  // namespace plucker
