#include "arrays.h"

#include <cmath>
#include <stdexcept>

namespace plucker {
namespace python {

std::string ShapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(a.shape(i));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

namespace {

py::array AsRealArray(const py::handle& obj, const char* name) {
  py::array a = py::array::ensure(obj);
  if (!a) throw py::type_error(std::string(name) + ": expected an array of numbers");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) +
                         ": expected a real (integer or float) array, got dtype " +
                         std::string(py::str(a.dtype())));
  return a;
}

void CheckFinite(const Eigen::MatrixXd& m, const char* name) {
  if (!m.allFinite()) throw py::value_error(std::string(name) + ": contains NaN or Inf");
}

}  // namespace

Eigen::MatrixXd SmallMatrix(const py::handle& obj, const char* name, int rows, int cols) {
  const py::array a = AsRealArray(obj, name);
  const bool vector = cols == 0;
  const bool ok = vector ? (a.ndim() == 1 && a.shape(0) == rows)
                         : (a.ndim() == 2 && a.shape(0) == rows && a.shape(1) == cols);
  if (!ok) {
    const std::string want = vector
                                 ? "(" + std::to_string(rows) + ",)"
                                 : "(" + std::to_string(rows) + ", " + std::to_string(cols) + ")";
    throw py::value_error(std::string(name) + ": expected shape " + want + ", got " + ShapeText(a));
  }
  const auto d = py::array_t<double, py::array::forcecast>::ensure(a);
  Eigen::MatrixXd m(rows, vector ? 1 : cols);
  const auto u = d.unchecked();
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < (vector ? 1 : cols); ++c) m(r, c) = vector ? u.data(r)[0] : *u.data(r, c);
  CheckFinite(m, name);
  return m;
}

namespace {

SE3d PoseFromMatrix(const Eigen::Matrix4d& m, const std::string& name) {
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  const double orthogonality =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality > 1e-6 || R.determinant() <= 0.0)
    throw py::value_error(name + ": the top-left 3x3 block is not a rotation (|R^T R - I| = " +
                          std::to_string(orthogonality) + ", det " +
                          std::to_string(R.determinant()) + ")");
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-12)
    throw py::value_error(name + ": the last row must be 0 0 0 1");
  return SE3d::FromMatrix(m);
}

}  // namespace

namespace {

// [tx, ty, tz, qx, qy, qz, qw] (TUM's order), the quaternion of norm 1 within 1e-6.
SE3d PoseFromTq(const Eigen::Matrix<double, 7, 1>& v, const std::string& name) {
  const Eigen::Quaterniond q(v(6), v(3), v(4), v(5));
  if (std::abs(q.norm() - 1.0) > 1e-6)
    throw py::value_error(name + ": the quaternion (qx, qy, qz, qw) must have norm 1, has " +
                          std::to_string(q.norm()));
  return SE3d(q, v.head<3>());
}

bool IsTq(const py::handle& obj) {
  const py::array a = py::array::ensure(obj);
  return a && a.ndim() == 1 && a.shape(0) == 7;
}

}  // namespace

SE3d Pose(const py::handle& obj, const char* name) {
  if (IsTq(obj)) return PoseFromTq(Vec<7>(obj, name), name);
  return PoseFromMatrix(Mat<4, 4>(obj, name), name);
}

std::vector<SE3d> Poses(const py::handle& obj, const char* name) {
  const py::array a = AsRealArray(obj, name);
  if (a.ndim() == 2 && a.shape(1) == 7) {  // rows tx ty tz qx qy qz qw
    const Eigen::MatrixXd m = SmallMatrix(a, name, static_cast<int>(a.shape(0)), 7);
    std::vector<SE3d> poses;
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      poses.push_back(
          PoseFromTq(m.row(i).transpose(), std::string(name) + "[" + std::to_string(i) + "]"));
    return poses;
  }
  if (a.ndim() != 3 || a.shape(1) != 4 || a.shape(2) != 4)
    throw py::value_error(std::string(name) + ": expected shape (N, 4, 4) or (N, 7), got " +
                          ShapeText(a));
  const auto d = py::array_t<double, py::array::forcecast>::ensure(a);
  const auto u = d.unchecked<3>();
  std::vector<SE3d> poses;
  poses.reserve(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = u(i, r, c);
    const std::string what = std::string(name) + "[" + std::to_string(i) + "]";
    CheckFinite(m, what.c_str());
    poses.push_back(PoseFromMatrix(m, what));
  }
  return poses;
}

PinholeIntrinsics Intrinsics(const py::handle& obj) {
  const Eigen::Vector4d k = Vec<4>(obj, "K");
  PinholeIntrinsics K;
  K.fx = k(0);
  K.fy = k(1);
  K.cx = k(2);
  K.cy = k(3);
  if (!K.IsValid()) throw py::value_error("K: expected (fx, fy, cx, cy) with fx, fy > 0");
  return K;
}

py::array_t<double> ToArray(const Eigen::MatrixXd& m) {
  py::array_t<double> a({m.rows(), m.cols()});
  auto w = a.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) w(r, c) = m(r, c);
  return a;
}

py::array_t<double> ToVector(const Eigen::VectorXd& v) {
  py::array_t<double> a(v.size());
  std::copy(v.data(), v.data() + v.size(), a.mutable_data());
  return a;
}

py::array_t<double> PoseMatrix(const SE3d& T) { return ToArray(T.Matrix()); }

namespace {
Eigen::Matrix<double, 1, 7> TqRow(const SE3d& T) {
  const Eigen::Quaterniond& q = T.rotation();
  Eigen::Matrix<double, 1, 7> row;
  row << T.translation().transpose(), q.x(), q.y(), q.z(), q.w();
  return row;
}
}  // namespace

py::array_t<double> PoseTq(const SE3d& T) { return ToVector(TqRow(T).transpose()); }

py::array_t<double> PosesTq(const std::vector<SE3d>& T) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(T.size()), 7);
  for (std::size_t i = 0; i < T.size(); ++i) m.row(static_cast<Eigen::Index>(i)) = TqRow(T[i]);
  return ToArray(m);
}

py::array_t<double> PoseMatrices(const std::vector<SE3d>& T) {
  py::array_t<double> a({static_cast<py::ssize_t>(T.size()), py::ssize_t{4}, py::ssize_t{4}});
  auto w = a.mutable_unchecked<3>();
  for (std::size_t i = 0; i < T.size(); ++i) {
    const Eigen::Matrix4d m = T[i].Matrix();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) w(static_cast<py::ssize_t>(i), r, c) = m(r, c);
  }
  return a;
}

py::array_t<double> PointsArray(std::vector<Eigen::Vector3d>&& points) {
  auto* owned = new std::vector<Eigen::Vector3d>(std::move(points));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<Eigen::Vector3d>*>(p); });
  const py::ssize_t n = static_cast<py::ssize_t>(owned->size());
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "Vector3d must be packed");
  return py::array_t<double>({n, py::ssize_t{3}},
                             {py::ssize_t{3 * sizeof(double)}, py::ssize_t{sizeof(double)}},
                             owned->empty() ? nullptr : owned->front().data(), owner);
}

py::array_t<double> DoubleArray(std::vector<double>&& values) {
  auto* owned = new std::vector<double>(std::move(values));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  return py::array_t<double>({static_cast<py::ssize_t>(owned->size())},
                             {py::ssize_t{sizeof(double)}}, owned->data(), owner);
}

// The scan as numpy: points (N, 3) float64 (a view of the scan's memory), intensity, ring, time
// (empty arrays when the file has none) and the scan start time.
py::dict ScanDict(LidarScan&& scan) {
  py::dict d;
  d["timestamp"] = scan.timestamp;
  d["intensity"] =
      py::array_t<float>(static_cast<py::ssize_t>(scan.intensity.size()), scan.intensity.data());
  d["ring"] = py::array_t<int>(static_cast<py::ssize_t>(scan.ring.size()), scan.ring.data());
  d["time"] = DoubleArray(std::move(scan.time));
  d["points"] = PointsArray(std::move(scan.points));
  return d;
}

}  // namespace python
}  // namespace plucker
