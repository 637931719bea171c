#include "plucker/eval/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace plucker {
namespace eval {
namespace {

constexpr char kFont[] = "DejaVu Sans, Helvetica, Arial, sans-serif";
constexpr char kGtColor[] = "#222222";
constexpr char kEstColor[] = "#1f77b4";
constexpr char kGridColor[] = "#e3e3e3";
constexpr char kAxisColor[] = "#555555";
constexpr double kLegendRowHeight = 17.0;

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
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
      default:
        out += c;
    }
  }
  return out;
}

std::string F(double v) {  // a pixel coordinate
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", v);
  return buf;
}

std::string TickLabel(double v, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  if (std::abs(v) < 1e-9 * step) v = 0.0;
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

// A data rectangle mapped onto a pixel rectangle (y up in data, down in pixels).
struct Frame {
  double px = 0, py = 0, pw = 1, ph = 1;  // pixel rectangle
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;  // data ranges
  double X(double x) const { return px + (x - x0) / (x1 - x0) * pw; }
  double Y(double y) const { return py + ph - (y - y0) / (y1 - y0) * ph; }
};

void Text(std::ostringstream& s, double x, double y, const std::string& text, int size,
          const char* anchor = "start", const char* extra = "") {
  s << "<text x=\"" << F(x) << "\" y=\"" << F(y) << "\" font-size=\"" << size << "\" text-anchor=\""
    << anchor << "\" " << extra << ">" << Escape(text) << "</text>\n";
}

void Axes(std::ostringstream& s, const Frame& f, const std::string& x_label,
          const std::string& y_label) {
  const std::vector<double> xt = NiceTicks(f.x0, f.x1, 7);
  const std::vector<double> yt = NiceTicks(f.y0, f.y1, 7);
  s << "<g stroke=\"" << kGridColor << "\" stroke-width=\"1\">\n";
  for (double x : xt) {
    s << "<line x1=\"" << F(f.X(x)) << "\" y1=\"" << F(f.py) << "\" x2=\"" << F(f.X(x))
      << "\" y2=\"" << F(f.py + f.ph) << "\"/>\n";
  }
  for (double y : yt) {
    s << "<line x1=\"" << F(f.px) << "\" y1=\"" << F(f.Y(y)) << "\" x2=\"" << F(f.px + f.pw)
      << "\" y2=\"" << F(f.Y(y)) << "\"/>\n";
  }
  s << "</g>\n";
  s << "<rect x=\"" << F(f.px) << "\" y=\"" << F(f.py) << "\" width=\"" << F(f.pw) << "\" height=\""
    << F(f.ph) << "\" fill=\"none\" stroke=\"" << kAxisColor << "\"/>\n";
  s << "<g fill=\"#333333\">\n";
  const double x_step = xt.size() > 1 ? xt[1] - xt[0] : 1.0;
  const double y_step = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (double x : xt) Text(s, f.X(x), f.py + f.ph + 16, TickLabel(x, x_step), 11, "middle");
  for (double y : yt) Text(s, f.px - 6, f.Y(y) + 4, TickLabel(y, y_step), 11, "end");
  s << "</g>\n";
  Text(s, f.px + f.pw / 2, f.py + f.ph + 38, x_label, 13, "middle");
  const double ly = f.py + f.ph / 2, lx = f.px - 52;
  s << "<text x=\"" << F(lx) << "\" y=\"" << F(ly) << "\" font-size=\"13\" text-anchor=\"middle\" "
    << "transform=\"rotate(-90 " << F(lx) << " " << F(ly) << ")\">" << Escape(y_label)
    << "</text>\n";
}

void Polyline(std::ostringstream& s, const Frame& f, const std::vector<Eigen::Vector2d>& pts,
              const std::string& color, double width, const std::string& clip_id) {
  // Non-finite points break the line into pieces.
  std::vector<std::vector<const Eigen::Vector2d*>> pieces(1);
  for (const Eigen::Vector2d& p : pts) {
    if (p.allFinite()) {
      pieces.back().push_back(&p);
    } else if (!pieces.back().empty()) {
      pieces.emplace_back();
    }
  }
  for (const auto& piece : pieces) {
    if (piece.size() < 2) continue;
    s << "<polyline clip-path=\"url(#" << clip_id << ")\" fill=\"none\" stroke=\"" << color
      << "\" stroke-width=\"" << width << "\" stroke-linejoin=\"round\" points=\"";
    for (const Eigen::Vector2d* p : piece) s << F(f.X(p->x())) << "," << F(f.Y(p->y())) << " ";
    s << "\"/>\n";
  }
}

void Dots(std::ostringstream& s, const Frame& f, const std::vector<Eigen::Vector2d>& pts,
          const std::string& color, const std::string& clip_id) {
  s << "<g clip-path=\"url(#" << clip_id << ")\" fill=\"" << color << "\">\n";
  for (const Eigen::Vector2d& p : pts) {
    if (!p.allFinite()) continue;
    s << "<circle cx=\"" << F(f.X(p.x())) << "\" cy=\"" << F(f.Y(p.y())) << "\" r=\"2.2\"/>\n";
  }
  s << "</g>\n";
}

void StartMarker(std::ostringstream& s, double x, double y, const std::string& color) {
  s << "<circle cx=\"" << F(x) << "\" cy=\"" << F(y) << "\" r=\"6\" fill=\"" << color
    << "\" stroke=\"white\" stroke-width=\"1.5\"/>\n";
}
void EndMarker(std::ostringstream& s, double x, double y, const std::string& color) {
  s << "<rect x=\"" << F(x - 5.5) << "\" y=\"" << F(y - 5.5)
    << "\" width=\"11\" height=\"11\" fill=\"" << color
    << "\" stroke=\"white\" stroke-width=\"1.5\"/>\n";
}

// Legend entries laid out in a row starting at (x, y); returns nothing.
struct LegendEntry {
  std::string label;
  std::string color;
  char kind;  // 'l' line, 'o' start circle, 's' end square, 'd' dots
};
double LegendEntryWidth(const LegendEntry& e) {
  return 30 + 6.8 * static_cast<double>(e.label.size()) + 16;
}

// Rows needed to lay out `entries` within `width` pixels.
int LegendRows(const std::vector<LegendEntry>& entries, double width) {
  int rows = entries.empty() ? 0 : 1;
  double x = 0;
  for (const LegendEntry& e : entries) {
    if (x > 0 && x + LegendEntryWidth(e) > width) {
      ++rows;
      x = 0;
    }
    x += LegendEntryWidth(e);
  }
  return rows;
}

// Legend entries laid out in rows of at most `width` pixels from (x, y) downwards.
void Legend(std::ostringstream& s, double x0, double y, double width,
            const std::vector<LegendEntry>& entries) {
  double x = x0;
  for (const LegendEntry& e : entries) {
    if (x > x0 && x - x0 + LegendEntryWidth(e) > width) {
      x = x0;
      y += kLegendRowHeight;
    }
    switch (e.kind) {
      case 'l':
        s << "<line x1=\"" << F(x) << "\" y1=\"" << F(y - 4) << "\" x2=\"" << F(x + 24)
          << "\" y2=\"" << F(y - 4) << "\" stroke=\"" << e.color << "\" stroke-width=\"2.5\"/>\n";
        break;
      case 'o':
        StartMarker(s, x + 12, y - 4, e.color);
        break;
      case 's':
        EndMarker(s, x + 12, y - 4, e.color);
        break;
      default:
        s << "<circle cx=\"" << F(x + 12) << "\" cy=\"" << F(y - 4) << "\" r=\"3\" fill=\""
          << e.color << "\"/>\n";
    }
    Text(s, x + 30, y, e.label, 12);
    x += LegendEntryWidth(e);
  }
}

// Expands [lo, hi] so that it is not empty.
void NonEmptyRange(double* lo, double* hi) {
  if (!(*hi > *lo)) {
    const double pad = std::max(1.0, std::abs(*lo) * 0.05);
    *lo -= pad;
    *hi += pad;
  }
}

const char* AxisName(int i) { return i == 0 ? "x" : i == 1 ? "y" : "z"; }

// A panel of series against x in `f` (its pixel rectangle set), the title at y = title_y and the
// legend at legend_y; the message when there is nothing to plot. clip: the clipPath id.
void DrawSeriesPanel(std::ostringstream& s, Frame f, double title_y, double legend_y,
                     const SeriesPanel& panel, const std::string& clip) {
  std::vector<LegendEntry> legend;
  for (const PlotSeries& series : panel.series) {
    legend.push_back({series.label, series.color, series.line ? 'l' : 'd'});
  }
  Text(s, f.px + f.pw / 2, title_y, panel.title, 14, "middle", "font-weight=\"bold\"");
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const PlotSeries& series : panel.series) {
    for (const Eigen::Vector2d& p : series.points) {
      if (!p.allFinite()) continue;
      x0 = std::min(x0, p.x());
      x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y());
      y1 = std::max(y1, p.y());
    }
  }
  if (x1 >= x0) {
    if (panel.zero_line) y0 = std::min(y0, 0.0);
    const double span = y1 - y0;
    y1 = y1 + 0.06 * span;
    if (!panel.zero_line) y0 = y0 - 0.06 * span;
    NonEmptyRange(&x0, &x1);
    NonEmptyRange(&y0, &y1);
    f.x0 = x0;
    f.x1 = x1;
    f.y0 = y0;
    f.y1 = y1;
    Axes(s, f, panel.x_label, panel.y_label);
    for (const PlotSeries& series : panel.series) {
      if (series.line) Polyline(s, f, series.points, series.color, 1.6, clip);
      if (series.markers) Dots(s, f, series.points, series.color, clip);
    }
    Legend(s, f.px, legend_y, f.pw, legend);
    return;
  }
  s << "<rect x=\"" << F(f.px) << "\" y=\"" << F(f.py) << "\" width=\"" << F(f.pw) << "\" height=\""
    << F(f.ph) << "\" fill=\"#fafafa\" stroke=\"" << kAxisColor << "\"/>\n";
  // Word-wrapped message (about 7.5 px a character at 14 px).
  const std::string message = panel.message.empty() ? "nothing to plot" : panel.message;
  const std::size_t max_chars = static_cast<std::size_t>(std::max(10.0, f.pw / 7.8));
  std::vector<std::string> lines(1);
  std::istringstream words(message);
  for (std::string word; words >> word;) {
    if (!lines.back().empty() && lines.back().size() + 1 + word.size() > max_chars) {
      lines.emplace_back();
    }
    lines.back() += (lines.back().empty() ? "" : " ") + word;
  }
  const double y_first = f.py + f.ph / 2 - 10.0 * (lines.size() - 1);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    Text(s, f.px + f.pw / 2, y_first + 20.0 * i, lines[i], 14, "middle", "fill=\"#aa3333\"");
  }
}

void SvgHeader(std::ostringstream& s, double W, double H) {
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" viewBox=\"0 0 " << W << " " << H << "\" font-family=\"" << kFont << "\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
}

}  // namespace

bool ParsePlotPlane(const std::string& name, PlotPlane* plane) {
  if (name == "auto")
    *plane = PlotPlane::kAuto;
  else if (name == "xy")
    *plane = PlotPlane::kXY;
  else if (name == "xz")
    *plane = PlotPlane::kXZ;
  else if (name == "yz")
    *plane = PlotPlane::kYZ;
  else
    return false;
  return true;
}

std::pair<int, int> PlotAxes(const std::vector<Eigen::Vector3d>& positions, PlotPlane plane) {
  switch (plane) {
    case PlotPlane::kXY:
      return {0, 1};
    case PlotPlane::kXZ:
      return {0, 2};
    case PlotPlane::kYZ:
      return {1, 2};
    case PlotPlane::kAuto:
      break;
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Eigen::Vector3d& p : positions) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (!(hi.x() >= lo.x())) return {0, 1};
  const Eigen::Vector3d extent = hi - lo;
  // Drop the axis of smallest extent; ties keep x-y.
  int drop = 2;
  if (extent.y() < extent(drop)) drop = 1;
  if (extent.x() < extent(drop)) drop = 0;
  if (drop == 0) return {1, 2};
  if (drop == 1) return {0, 2};
  return {0, 1};
}

std::vector<double> NiceTicks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  if (hi < lo) std::swap(lo, hi);
  double range = hi - lo;
  if (range <= 0.0) range = std::max(std::abs(lo), 1.0);
  const double raw = range / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double step = (norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0) * mag;
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (int i = 0; i < 1000; ++i) {
    const double v = first + i * step;
    if (v > hi + 1e-9 * step) break;
    ticks.push_back(v);
  }
  return ticks;
}

std::string RenderSeriesFigureSvg(const SeriesFigure& figure) {
  const int columns = std::max(1, figure.columns);
  const int rows = std::max<int>(1, (figure.panels.size() + columns - 1) / columns);
  const double W = std::max(600, figure.width), H = 70 + rows * std::max(240, figure.panel_height);
  std::ostringstream s;
  SvgHeader(s, W, H);
  Text(s, W / 2, 30, figure.title, 18, "middle", "font-weight=\"bold\"");
  if (!figure.subtitle.empty()) {
    Text(s, W / 2, 50, figure.subtitle, 12, "middle", "fill=\"#555555\"");
  }
  const double cell_w = W / columns, cell_h = (H - 70) / rows;
  for (std::size_t i = 0; i < figure.panels.size(); ++i) {
    const double cx = cell_w * (i % columns), cy = 70 + cell_h * (i / columns);
    const SeriesPanel& panel = figure.panels[i];
    std::vector<LegendEntry> legend;
    for (const PlotSeries& series : panel.series) legend.push_back({series.label, "", 'l'});
    const int legend_rows = LegendRows(legend, cell_w - 112);
    Frame f;
    f.px = cx + 82;
    f.py = cy + 56 + kLegendRowHeight * std::max(0, legend_rows - 1);
    f.pw = cell_w - 112;
    f.ph = cy + cell_h - 52 - f.py;
    const std::string clip = "clipS" + std::to_string(i);
    s << "<defs><clipPath id=\"" << clip << "\"><rect x=\"" << F(f.px - 4) << "\" y=\""
      << F(f.py - 4) << "\" width=\"" << F(f.pw + 8) << "\" height=\"" << F(f.ph + 8)
      << "\"/></clipPath></defs>\n";
    DrawSeriesPanel(s, f, cy + 20, cy + 42, panel, clip);
  }
  s << "</svg>\n";
  return s.str();
}

std::string StackSvgDocuments(const std::vector<std::string>& documents) {
  double W = 0.0, H = 0.0;
  std::vector<std::pair<std::string, double>> bodies;  // the inner <svg ...>...</svg>, its height
  for (const std::string& d : documents) {
    const std::size_t open = d.find("<svg");
    double w = 0.0, h = 0.0;
    if (open == std::string::npos ||
        std::sscanf(d.c_str() + open,
                    "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%lf\" "
                    "height=\"%lf\"",
                    &w, &h) != 2) {
      throw std::invalid_argument("StackSvgDocuments: not a document of this plotter");
    }
    bodies.emplace_back(d.substr(open), h);
    W = std::max(W, w);
    H += h;
  }
  std::ostringstream s;
  SvgHeader(s, W, H);
  double y = 0.0;
  for (const auto& [body, h] : bodies) {
    // A nested <svg> keeps its own viewport: placed at y by a group.
    s << "<g transform=\"translate(0," << F(y) << ")\">\n" << body << "</g>\n";
    y += h;
  }
  s << "</svg>\n";
  return s.str();
}

std::string RenderTrajectoryPlotSvg(const TrajectoryPlot& plot) {
  const double W = std::max(600, plot.width), H = std::max(360, plot.height);
  std::ostringstream s;
  SvgHeader(s, W, H);
  Text(s, W / 2, 30, plot.title, 18, "middle", "font-weight=\"bold\"");
  if (!plot.subtitle.empty()) Text(s, W / 2, 50, plot.subtitle, 12, "middle", "fill=\"#555555\"");

  // Legends first: their row count decides where the plot areas start.
  const std::vector<LegendEntry> left_legend = {{plot.label_gt, kGtColor, 'l'},
                                                {plot.label_est, kEstColor, 'l'},
                                                {"start", "#777777", 'o'},
                                                {"end", "#777777", 's'}};
  std::vector<LegendEntry> right_legend;
  for (const PlotSeries& series : plot.error_series) {
    right_legend.push_back({series.label, series.color, series.line ? 'l' : 'd'});
  }
  const double panel_width = W / 2 - 82 - 30;
  const int legend_rows =
      std::max(LegendRows(left_legend, panel_width), LegendRows(right_legend, panel_width));
  const double top = 118 + kLegendRowHeight * std::max(0, legend_rows - 1), bottom = H - 62;
  // ---- Left panel: top view, equal scale. ----
  Frame left;
  left.px = 82;
  left.py = top;
  left.pw = W / 2 - left.px - 30;
  left.ph = bottom - top;
  std::vector<Eigen::Vector3d> all = plot.positions_gt;
  all.insert(all.end(), plot.positions_est.begin(), plot.positions_est.end());
  const std::pair<int, int> axes =
      PlotAxes(plot.positions_gt.empty() ? all : plot.positions_gt, plot.plane);
  auto project = [&](const std::vector<Eigen::Vector3d>& p) {
    std::vector<Eigen::Vector2d> out;
    out.reserve(p.size());
    for (const Eigen::Vector3d& v : p) out.emplace_back(v(axes.first), v(axes.second));
    return out;
  };
  const std::vector<Eigen::Vector2d> gt2 = project(plot.positions_gt);
  const std::vector<Eigen::Vector2d> est2 = project(plot.positions_est);
  {
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const auto* v : {&gt2, &est2}) {
      for (const Eigen::Vector2d& p : *v) {
        if (!p.allFinite()) continue;
        x0 = std::min(x0, p.x());
        x1 = std::max(x1, p.x());
        y0 = std::min(y0, p.y());
        y1 = std::max(y1, p.y());
      }
    }
    if (!(x1 >= x0)) x0 = x1 = y0 = y1 = 0.0;
    // Equal scale: metres per pixel the same on both axes, data centred in the panel.
    const double pad = 0.04;
    double dx = std::max(x1 - x0, 1e-3) * (1 + 2 * pad),
           dy = std::max(y1 - y0, 1e-3) * (1 + 2 * pad);
    const double m_per_px = std::max(dx / left.pw, dy / left.ph);
    dx = m_per_px * left.pw;
    dy = m_per_px * left.ph;
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    left.x0 = cx - dx / 2;
    left.x1 = cx + dx / 2;
    left.y0 = cy - dy / 2;
    left.y1 = cy + dy / 2;
  }
  Frame right;
  right.px = W / 2 + 82;
  right.py = top;
  right.pw = W - right.px - 30;
  right.ph = bottom - top;
  s << "<defs><clipPath id=\"clipL\"><rect x=\"" << F(left.px) << "\" y=\"" << F(left.py)
    << "\" width=\"" << F(left.pw) << "\" height=\"" << F(left.ph) << "\"/></clipPath>"
    << "<clipPath id=\"clipR\"><rect x=\"" << F(right.px - 4) << "\" y=\"" << F(right.py - 4)
    << "\" width=\"" << F(right.pw + 8) << "\" height=\"" << F(right.ph + 8)
    << "\"/></clipPath></defs>\n";
  Text(s, left.px + left.pw / 2, 82,
       std::string("Top view (") + AxisName(axes.first) + "-" + AxisName(axes.second) +
           " plane, equal scale)",
       14, "middle", "font-weight=\"bold\"");
  Axes(s, left, std::string(AxisName(axes.first)) + " [m]",
       std::string(AxisName(axes.second)) + " [m]");
  Polyline(s, left, gt2, kGtColor, 2.2, "clipL");
  Polyline(s, left, est2, kEstColor, 1.6, "clipL");
  for (const auto& [pts, color] :
       {std::make_pair(&gt2, kGtColor), std::make_pair(&est2, kEstColor)}) {
    if (pts->empty()) continue;
    StartMarker(s, left.X(pts->front().x()), left.Y(pts->front().y()), color);
    EndMarker(s, left.X(pts->back().x()), left.Y(pts->back().y()), color);
  }
  Legend(s, left.px, 104, left.pw, left_legend);

  // ---- Right panel: error along the trajectory. ----
  SeriesPanel panel;
  panel.title = plot.error_title;
  panel.x_label = plot.error_x_label;
  panel.y_label = plot.error_y_label;
  panel.series = plot.error_series;
  panel.message = plot.error_message;
  panel.zero_line = true;
  DrawSeriesPanel(s, right, 82, 104, panel, "clipR");
  s << "</svg>\n";
  return s.str();
}

}  // namespace eval
}  // namespace plucker
