// plucker evaluation: ATE, RPE and the KITTI metric on (N, 4, 4) pose arrays, as plain dicts.
#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "plucker/eval/alignment.h"
#include "plucker/eval/ate.h"
#include "plucker/eval/kitti_metric.h"
#include "plucker/eval/rpe.h"
#include "plucker/eval/statistics.h"

namespace plucker {
namespace python {

namespace {

eval::AlignmentMode Alignment(const std::string& name) {
  const auto mode = eval::ParseAlignmentMode(name);
  if (!mode) throw py::value_error("align: expected none, se3, sim3 or posyaw, got '" + name + "'");
  return *mode;
}

py::dict Statistics(const eval::ErrorStatistics& s) {
  py::dict d;
  d["count"] = s.count;
  d["rmse"] = s.rmse;
  d["mean"] = s.mean;
  d["median"] = s.median;
  d["std"] = s.std_dev;
  d["min"] = s.min;
  d["max"] = s.max;
  return d;
}

py::object Optional(const std::optional<double>& v) {
  return v ? py::object(py::float_(*v)) : py::object(py::none());
}

// The fields ATE and RPE share.
template <typename Result>
py::dict ErrorDict(Result&& r, eval::AlignmentMode align) {
  py::dict d;
  d["align"] = eval::AlignmentName(align);
  d["scale"] = r.alignment.scale;
  d["translation_m"] = Statistics(r.translation_m);
  d["rotation_deg"] = Statistics(r.rotation_deg);
  d["translation_errors"] = DoubleArray(std::move(r.translation_errors));
  d["rotation_errors_deg"] = DoubleArray(std::move(r.rotation_errors_deg));
  d["distance"] = DoubleArray(std::move(r.distance));
  d["aligned_estimate"] = PoseMatrices(r.aligned_estimate);
  return d;
}

}  // namespace

void RegisterEval(py::module_& m) {
  m.def(
      "ate",
      [](const py::handle& gt, const py::handle& est, const std::string& align) {
        eval::AteOptions o;
        o.align = Alignment(align);
        return ErrorDict(eval::ComputeAte(Poses(gt, "gt"), Poses(est, "est"), o), o.align);
      },
      py::arg("gt"), py::arg("est"), py::arg("align") = "se3",
      "Absolute trajectory error of est against gt (both (N, 4, 4), associated by index) after\n"
      "an alignment (none | se3 | sim3 | posyaw): translation_m / rotation_deg statistics (rmse,\n"
      "mean, median, std, min, max), per-pose errors and the aligned estimate.");
  m.def(
      "rpe",
      [](const py::handle& gt, const py::handle& est, double delta, const std::string& unit,
         const std::string& align) {
        eval::RpeOptions o;
        o.delta = delta;
        if (unit != "frames" && unit != "m")
          throw py::value_error("unit: expected frames or m, got '" + unit + "'");
        o.unit = unit == "m" ? eval::DeltaUnit::kMeters : eval::DeltaUnit::kFrames;
        o.align = Alignment(align);
        eval::RpeResult r = eval::ComputeRpe(Poses(gt, "gt"), Poses(est, "est"), o);
        std::vector<int> first = r.first, last = r.last;
        py::dict d = ErrorDict(std::move(r), o.align);
        d["first"] = first;
        d["last"] = last;
        return d;
      },
      py::arg("gt"), py::arg("est"), py::arg("delta") = 1.0, py::arg("unit") = "frames",
      py::arg("align") = "none",
      "Relative pose error over delta frames (unit='frames') or metres of path (unit='m').");
  m.def(
      "kitti_metric",
      [](const py::handle& gt, const py::handle& est, int step_size) {
        eval::KittiOptions o;
        o.step_size = step_size;
        const eval::KittiResult r = eval::ComputeKittiMetric(Poses(gt, "gt"), Poses(est, "est"), o);
        py::dict d;
        d["pose_count"] = r.pose_count;
        d["path_length"] = r.path_length;
        d["segment_count"] = r.segment_count;
        d["translation_error_percent"] = Optional(r.translation_error_percent);
        d["rotation_error_deg_per_100m"] = Optional(r.rotation_error_deg_per_100m);
        py::list per_length;
        for (const eval::KittiLengthResult& l : r.per_length) {
          py::dict e;
          e["length"] = l.length;
          e["segment_count"] = l.segment_count;
          e["translation_error_percent"] = Optional(l.translation_error_percent);
          e["rotation_error_deg_per_100m"] = Optional(l.rotation_error_deg_per_100m);
          per_length.append(e);
        }
        d["per_length"] = per_length;
        return d;
      },
      py::arg("gt"), py::arg("est"), py::arg("step_size") = 10,
      "The KITTI odometry metric (devkit definition, 100..800 m segments) of cam0 poses; the\n"
      "errors are None when the path is shorter than 100 m (no segment).");
}

}  // namespace python
}  // namespace plucker
