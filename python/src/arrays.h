// numpy <-> Eigen for the bindings: shape, dtype, contiguity and finiteness checked with messages
// that name the argument (ValueError / TypeError in Python), never a crash or a silent cast.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/sensor/lidar_scan.h"

namespace plucker {
namespace python {

namespace py = pybind11;

// A small real array (int or float dtype, any strides) of exactly `rows` x `cols` values (cols 0:
// a vector of `rows`), finite; copied to doubles. Lists and tuples are accepted too.
Eigen::MatrixXd SmallMatrix(const py::handle& obj, const char* name, int rows, int cols);

template <int R>
Eigen::Matrix<double, R, 1> Vec(const py::handle& obj, const char* name) {
  return SmallMatrix(obj, name, R, 0);
}
template <int R, int C>
Eigen::Matrix<double, R, C> Mat(const py::handle& obj, const char* name) {
  return SmallMatrix(obj, name, R, C);
}

// A 4x4 homogeneous rigid transform (rotation checked orthonormal to 1e-6, last row 0 0 0 1), or
// (7,) [tx, ty, tz, qx, qy, qz, qw] (TUM's order, the quaternion of norm 1 within 1e-6): the
// library's own numbers, exact where a rotation matrix is not (its quaternion rounds).
SE3d Pose(const py::handle& obj, const char* name);
// (N, 4, 4), a list of 4x4, or (N, 7) rows tx ty tz qx qy qz qw: N >= 0 poses.
std::vector<SE3d> Poses(const py::handle& obj, const char* name);

// Pinhole intrinsics from K = (fx, fy, cx, cy), fx, fy > 0.
PinholeIntrinsics Intrinsics(const py::handle& obj);

// numpy outputs (copies of small Eigen values; C order).
py::array_t<double> ToArray(const Eigen::MatrixXd& m);
py::array_t<double> ToVector(const Eigen::VectorXd& v);
py::array_t<double> PoseMatrix(const SE3d& T);
py::array_t<double> PoseMatrices(const std::vector<SE3d>& T);
// (7,) / (N, 7) [tx, ty, tz, qx, qy, qz, qw]: the pose's own quaternion and translation.
py::array_t<double> PoseTq(const SE3d& T);
py::array_t<double> PosesTq(const std::vector<SE3d>& T);
// An (N, 3) view of the points, which the array then owns (no copy).
py::array_t<double> PointsArray(std::vector<Eigen::Vector3d>&& points);
py::array_t<double> DoubleArray(std::vector<double>&& values);
// A LiDAR scan: points (N, 3) float64 (a view of the scan's memory), intensity, ring, time
// (empty arrays when it has none) and the scan start time (read_pcd, Bag messages).
py::dict ScanDict(LidarScan&& scan);

// The shape of an array as "(3, 4)", for messages.
std::string ShapeText(const py::array& a);

}  // namespace python
}  // namespace plucker
