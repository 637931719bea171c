// plucker.LidarOdometry: the scan-to-map LiDAR odometry of `plucker lidar`, fed numpy scans. The
// options are the rows of the CLI's options table (apps/plucker/lidar_options_table.h): the same
// keys, types, defaults and error messages as `plucker config lidar` and `--config`.
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "arrays.h"
#include "bindings.h"
#include "lidar_options_table.h"
#include "options.h"
#include "plucker/lidar/odometry.h"
#include "plucker/sensor/lidar_model.h"

namespace plucker {
namespace python {

namespace {

using app::LidarConfig;
using app::LidarOption;

// Sets one option (a dotted key, or a group given as a dict) through the table.
void SetOption(const std::string& key, const py::handle& value, LidarConfig* config) {
  if (py::isinstance<py::dict>(value)) {
    for (const auto& kv : value.cast<py::dict>())
      SetOption(key + "." + std::string(py::str(kv.first)), kv.second, config);
    return;
  }
  const std::vector<LidarOption>& table = app::LidarOptionTable();
  const auto it =
      std::find_if(table.begin(), table.end(), [&](const LidarOption& o) { return o.key == key; });
  if (it == table.end())
    throw py::value_error("LidarOdometry: unknown option '" + key +
                          "' (plucker.lidar_options() lists every key with its default)");
  try {
    it->set(YAML::Node(ScalarText(value, key, "LidarOdometry")), config);
  } catch (const std::exception& e) {
    throw py::value_error("LidarOdometry: option '" + key + "': " + e.what());
  }
}

class PyLidarOdometry {
 public:
  PyLidarOdometry(const py::object& config_path, const std::string& sensor, int threads,
                  const py::kwargs& options) {
    if (!config_path.is_none()) app::LoadLidarConfig(config_path.cast<std::string>(), &config_);
    for (const auto& kv : options) SetOption(std::string(py::str(kv.first)), kv.second, &config_);
    if (sensor != "auto") sensor::LidarModelFromName(sensor);  // validates the name
    if (threads < 1) throw py::value_error("LidarOdometry: threads must be >= 1");
    lidar::LidarOdometryOptions o = config_.odometry;
    if (sensor != "auto") o.sensor = sensor;  // else the config key `sensor` (default auto)
    o.num_threads = threads;
    odometry_ = std::make_unique<lidar::LidarOdometry>(o);
  }

  py::array_t<double> Register(const py::array& points, const py::object& timestamp) {
    LidarScan scan = ToScan(points);
    double stamp = times_.empty() ? 0.0 : times_.back() + 0.1;
    if (!timestamp.is_none()) {
      stamp = timestamp.cast<double>();
      if (!std::isfinite(stamp)) throw py::value_error("register: timestamp is not finite");
      scan.timestamp = stamp;
    }
    lidar::FrameResult r;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      r = odometry_->ProcessScan(std::move(scan));
      times_.push_back(stamp);
      last_ = r;
    }
    return PoseMatrix(r.T_w_s);
  }

  py::array_t<double> Poses() {
    std::lock_guard<std::mutex> lock(mutex_);
    return PoseMatrices(odometry_->poses());
  }
  py::array_t<double> Times() {
    std::lock_guard<std::mutex> lock(mutex_);
    return DoubleArray(std::vector<double>(times_));
  }

  py::array_t<double> LocalMap(const std::string& which) {
    if (which != "all" && which != "edges" && which != "planes")
      throw py::value_error("local_map: expected 'all', 'edges' or 'planes', got '" + which + "'");
    std::vector<Eigen::Vector3d> points;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (which != "planes") points = odometry_->edge_map().Points();
      if (which != "edges") {
        std::vector<Eigen::Vector3d> planes = odometry_->plane_map().Points();
        points.insert(points.end(), planes.begin(), planes.end());
      }
    }
    return PointsArray(std::move(points));
  }

  py::dict LastFrame() {
    std::lock_guard<std::mutex> lock(mutex_);
    py::dict d;
    d["ok"] = last_.ok;
    d["error"] = last_.error;
    d["edge_points"] = last_.edge_points;
    d["plane_points"] = last_.plane_points;
    d["edge_correspondences"] = last_.edge_correspondences;
    d["plane_correspondences"] = last_.plane_correspondences;
    d["association_rounds"] = last_.association_rounds;
    d["solver_iterations"] = last_.solver_iterations;
    d["final_cost"] = last_.final_cost;
    d["degenerate"] = last_.degeneracy.degenerate;
    d["deskewed"] = last_.deskewed;
    d["map_points"] = last_.map_points;
    return d;
  }

  std::string ConfigYaml() const { return app::LidarConfigYaml(config_); }

 private:
  // (N, 3) or (N, 4) float32/float64, C-contiguous, finite; the 4th column is the intensity.
  static LidarScan ToScan(const py::array& a) {
    const char kind = a.dtype().kind();
    const bool f32 = kind == 'f' && a.itemsize() == 4, f64 = kind == 'f' && a.itemsize() == 8;
    if (!f32 && !f64)
      throw py::type_error("register: points must be float32 or float64, got dtype " +
                           std::string(py::str(a.dtype())));
    if (a.ndim() != 2 || (a.shape(1) != 3 && a.shape(1) != 4))
      throw py::value_error("register: points must have shape (N, 3) or (N, 4), got " +
                            ShapeText(a));
    if (!(a.flags() & py::array::c_style))
      throw py::value_error("register: points must be C-contiguous (np.ascontiguousarray(points))");
    const std::size_t n = static_cast<std::size_t>(a.shape(0)),
                      cols = static_cast<std::size_t>(a.shape(1));
    LidarScan scan;
    scan.points.resize(n);
    if (cols == 4) scan.intensity.resize(n);
    const auto read = [&](auto* data) {
      for (std::size_t i = 0; i < n; ++i) {
        const auto* row = data + i * cols;
        scan.points[i] = Eigen::Vector3d(row[0], row[1], row[2]);
        if (!scan.points[i].allFinite())
          throw py::value_error("register: point " + std::to_string(i) + " is not finite");
        if (cols == 4) scan.intensity[i] = static_cast<float>(row[3]);
      }
    };
    if (f32)
      read(static_cast<const float*>(a.data()));
    else
      read(static_cast<const double*>(a.data()));
    if (n == 0) throw py::value_error("register: the scan has no points");
    return scan;
  }

  LidarConfig config_;
  std::unique_ptr<lidar::LidarOdometry> odometry_;
  std::vector<double> times_;
  lidar::FrameResult last_;
  std::mutex mutex_;
};

}  // namespace

void RegisterLidar(py::module_& m) {
  py::class_<PyLidarOdometry>(
      m, "LidarOdometry", "LOAM-style LiDAR odometry (plucker lidar): register scans one by one.")
      .def(
          py::init<const py::object&, const std::string&, int, const py::kwargs&>(),
          py::arg("config") = py::none(), py::arg("sensor") = "auto", py::arg("threads") = 1,
          "Options are the keys of `plucker config lidar`, dotted (**{'features.min_range': 2.0})\n"
          "or grouped (features={'min_range': 2.0}); config: a YAML file as --config; sensor:\n"
          "auto | hdl64 | vlp32 | vlp16 | os1-64 | os1-128 | generic; threads as --threads. Unknown keys and wrong types raise\n"
          "ValueError naming the key.")
      .def("register", &PyLidarOdometry::Register, py::arg("points"),
           py::arg("timestamp") = py::none(),
           "Registers one scan (N, 3) or (N, 4) (x y z [intensity], float32 or float64, LiDAR "
           "frame,\n"
           "in firing order for KITTI) taken at `timestamp` seconds; returns the LiDAR-frame pose\n"
           "T_w_l (4, 4) of the scan, the first scan at identity. The GIL is released meanwhile.")
      .def_property_readonly("poses", &PyLidarOdometry::Poses,
                             "T_w_l of every scan so far (N, 4, 4).")
      .def_property_readonly("times", &PyLidarOdometry::Times,
                             "The scans' timestamps (N,) (previous + 0.1 s when not given).")
      .def_property_readonly(
          "last_frame", &PyLidarOdometry::LastFrame,
          "Statistics of the last registered scan (ok, error, correspondences, ...).")
      .def("local_map", &PyLidarOdometry::LocalMap, py::arg("which") = "all",
           "The odometry's local map points (N, 3) in the world (first scan's LiDAR) frame:\n"
           "'all', 'edges' or 'planes'.")
      .def("config_yaml", &PyLidarOdometry::ConfigYaml,
           "The options in effect as a YAML file (the format of `plucker config lidar`).");
  m.def(
      "lidar_options",
      []() {
        py::dict d;
        const LidarConfig defaults;
        for (const LidarOption& o : app::LidarOptionTable()) d[o.key.c_str()] = o.get(defaults);
        return d;
      },
      "Every LidarOdometry option key with its default as YAML text (the rows of `plucker config "
      "lidar`).");
  m.def(
      "lidar_config_yaml", []() { return app::LidarConfigYaml(LidarConfig()); },
      "The text `plucker config lidar` prints: every option with its default.");
}

}  // namespace python
}  // namespace plucker
