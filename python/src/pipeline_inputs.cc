#include "pipeline_inputs.h"

#include <cmath>
#include <set>
#include <string>

#include "arrays.h"

namespace plucker {
namespace python {

namespace {

void CheckKeys(const py::dict& d, const std::set<std::string>& known, const char* who,
               const char* what) {
  for (const auto& kv : d) {
    const std::string key = std::string(py::str(kv.first));
    if (!known.count(key)) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      throw py::value_error(std::string(who) + ": unknown " + what + " key '" + key +
                            "' (expected " + list + ")");
    }
  }
}

py::dict DictArg(const py::handle& obj, const char* who, const char* what) {
  if (!py::isinstance<py::dict>(obj))
    throw py::type_error(std::string(who) + ": " + what + " must be a dict (as read_euroc gives)");
  return obj.cast<py::dict>();
}

int IntArg(const py::handle& v, const std::string& name) {
  // Python and numpy integers (anything with __index__), not bools.
  if (py::isinstance<py::bool_>(v) || !py::hasattr(v, "__index__"))
    throw py::type_error(name + ": expected an integer");
  return py::int_(v.attr("__index__")()).cast<int>();
}

// A 2-D real array of `cols` columns (rows >= 0) as doubles, finite.
Eigen::MatrixXd Rows(const py::handle& obj, int cols, const std::string& name) {
  const py::array a = py::array::ensure(obj);
  if (!a) throw py::type_error(name + ": expected an array of numbers");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(name + ": expected a real array, got dtype " +
                         std::string(py::str(a.dtype())));
  if (a.ndim() != 2 || a.shape(1) != cols)
    throw py::value_error(name + ": expected shape (N, " + std::to_string(cols) + "), got " +
                          ShapeText(a));
  const auto d = py::array_t<double, py::array::forcecast>::ensure(a);
  const auto u = d.unchecked<2>();
  Eigen::MatrixXd m(a.shape(0), cols);
  for (py::ssize_t r = 0; r < a.shape(0); ++r)
    for (int c = 0; c < cols; ++c) m(r, c) = u(r, c);
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    if (!m.row(r).allFinite())
      throw py::value_error(name + ": row " + std::to_string(r) + " contains NaN or Inf");
  return m;
}

}  // namespace

double TimeArg(const py::handle& t, const char* who) {
  if (!py::isinstance<py::float_>(t) && !py::isinstance<py::int_>(t) &&
      !py::hasattr(t, "__float__"))
    throw py::type_error(std::string(who) + ": t must be a number (seconds)");
  const double v = t.cast<double>();
  if (!std::isfinite(v)) throw py::value_error(std::string(who) + ": t is not finite");
  return v;
}

sensor::Camera CameraArg(const py::handle& obj, const char* who) {
  const py::dict d = DictArg(obj, who, "camera");
  // The extra keys of read_euroc's camera dict are accepted (and ignored) so that it can be
  // passed as it is.
  CheckKeys(d, {"K", "width", "height", "distortion", "T_b_c", "T_b_c_tq", "rate_hz"}, who,
            "camera");
  for (const char* key : {"K", "width", "height"})
    if (!d.contains(key)) throw py::value_error(std::string(who) + ": camera needs '" + key + "'");
  sensor::Camera c;
  const Eigen::Vector4d K = Vec<4>(d["K"], "camera['K']");
  c.K = {K(0), K(1), K(2), K(3)};
  c.width = IntArg(d["width"], "camera['width']");
  c.height = IntArg(d["height"], "camera['height']");
  if (d.contains("distortion")) {
    const Eigen::Vector4d k = Vec<4>(d["distortion"], "camera['distortion']");
    c.distortion = {k(0), k(1), k(2), k(3)};
  }
  const std::string problem = c.Problem();
  if (!problem.empty()) throw py::value_error(std::string(who) + ": camera: " + problem);
  return c;
}

sensor::ImuModel ImuModelArg(const py::handle& obj, const char* who) {
  const py::dict d = DictArg(obj, who, "imu_model");
  sensor::ImuModel m;
  const std::pair<const char*, double*> fields[] = {
      {"rate_hz", &m.rate_hz},
      {"gyro_noise_density", &m.gyro_noise_density},
      {"accel_noise_density", &m.accel_noise_density},
      {"gyro_bias_random_walk", &m.gyro_bias_random_walk},
      {"accel_bias_random_walk", &m.accel_bias_random_walk}};
  std::set<std::string> known;
  for (const auto& f : fields) known.insert(f.first);
  CheckKeys(d, known, who, "imu_model");
  for (const auto& [key, field] : fields) {
    if (!d.contains(key)) continue;
    *field = d[key].cast<double>();
    if (!std::isfinite(*field) || *field <= 0.0)
      throw py::value_error(std::string(who) + ": imu_model['" + key +
                            "'] must be a positive finite number");
  }
  return m;
}

py::dict ImuModelDict(const sensor::ImuModel& m) {
  py::dict d;
  d["rate_hz"] = m.rate_hz;
  d["gyro_noise_density"] = m.gyro_noise_density;
  d["accel_noise_density"] = m.accel_noise_density;
  d["gyro_bias_random_walk"] = m.gyro_bias_random_walk;
  d["accel_bias_random_walk"] = m.accel_bias_random_walk;
  return d;
}

std::vector<sensor::ImuSample> ImuRows(const py::handle& obj, const char* who) {
  const Eigen::MatrixXd m = Rows(obj, 7, std::string(who) + ": samples");
  std::vector<sensor::ImuSample> samples(static_cast<std::size_t>(m.rows()));
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    sensor::ImuSample& s = samples[static_cast<std::size_t>(r)];
    s.t = m(r, 0);
    s.gyro = m.row(r).segment<3>(1).transpose();
    s.accel = m.row(r).segment<3>(4).transpose();
  }
  return samples;
}

cv::Mat GrayImageView(const py::array& a, const char* who) {
  if (a.dtype().kind() != 'u' || a.itemsize() != 1)
    throw py::type_error(std::string(who) + ": image must be uint8 (8-bit grayscale), got dtype " +
                         std::string(py::str(a.dtype())));
  if (a.ndim() != 2)
    throw py::value_error(std::string(who) + ": image must have shape (H, W), got " + ShapeText(a));
  if (a.shape(0) == 0 || a.shape(1) == 0) throw py::value_error(std::string(who) + ": empty image");
  if (a.strides(1) != 1 || a.strides(0) < a.shape(1))
    throw py::value_error(std::string(who) +
                          ": image rows must be contiguous (np.ascontiguousarray(image))");
  // cv::Mat has no const view: the pipelines only read the image (undistorted into a new one).
  return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), CV_8UC1,
                 const_cast<void*>(a.data()), static_cast<std::size_t>(a.strides(0)));
}

window::FrameInput FrameArg(double t, const py::handle& points, const py::handle& segments,
                            int frame, const char* who) {
  window::FrameInput f;
  f.time = t;
  if (!points.is_none()) {
    const Eigen::MatrixXd p = Rows(points, 3, std::string(who) + ": points");
    for (Eigen::Index r = 0; r < p.rows(); ++r) {
      sensor::PointObservation o;
      o.frame = frame;
      o.point_id = static_cast<int>(p(r, 0));
      o.uv = p.row(r).segment<2>(1).transpose();
      f.points.push_back(o);
    }
  }
  if (!segments.is_none()) {
    const Eigen::MatrixXd s = Rows(segments, 5, std::string(who) + ": segments");
    for (Eigen::Index r = 0; r < s.rows(); ++r) {
      sensor::SegmentObservation o;
      o.frame = frame;
      o.line_id = static_cast<int>(s(r, 0));
      o.s_px = s.row(r).segment<2>(1).transpose();
      o.e_px = s.row(r).segment<2>(3).transpose();
      f.segments.push_back(o);
    }
  }
  return f;
}

py::dict WindowDict(const window::WindowFrameResult& r) {
  py::dict d;
  d["ok"] = r.ok;
  d["pnp_fallback"] = r.pnp_fallback;
  d["keyframe"] = r.keyframe;
  d["tracked_points"] = r.tracked_points;
  d["tracked_lines"] = r.tracked_lines;
  d["new_points"] = r.new_points;
  d["new_lines"] = r.new_lines;
  d["window_points"] = r.window_points;
  d["window_lines"] = r.window_lines;
  d["window_keyframes"] = r.window_keyframes;
  d["tracking_iterations"] = r.tracking_iterations;
  d["window_iterations"] = r.window_iterations;
  d["initial_cost"] = r.initial_cost;
  d["final_cost"] = r.final_cost;
  d["residuals"] = r.residuals;
  d["marginalized_keyframes"] = r.marginalized_keyframes;
  d["imu_chi2"] = r.imu_chi2;
  return d;
}

}  // namespace python
}  // namespace plucker
