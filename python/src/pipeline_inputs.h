// The inputs and outputs of the online camera pipelines from Python (vio.cc, vo.cc): the camera
// and IMU model as dicts (the ones read_euroc returns), IMU samples, images as read-only views
// of uint8 arrays, a frame's observations, the window's per-frame statistics as a dict. Every
// bad input is a TypeError / ValueError naming the argument.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <mutex>
#include <opencv2/core.hpp>
#include <vector>

#include "plucker/sensor/camera.h"
#include "plucker/sensor/imu.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace python {

namespace py = pybind11;

// {"K": (fx, fy, cx, cy), "width", "height", "distortion": (k1, k2, p1, p2) optional}: a
// radial-tangential (or pinhole) camera; unknown keys raise. Checked with Camera::Problem().
sensor::Camera CameraArg(const py::handle& obj, const char* who);

// {"gyro_noise_density", "accel_noise_density", "gyro_bias_random_walk",
// "accel_bias_random_walk", "rate_hz"}: any subset (the others keep ImuModel's defaults).
sensor::ImuModel ImuModelArg(const py::handle& obj, const char* who);
py::dict ImuModelDict(const sensor::ImuModel& m);

// (N, 7) rows t, gyro xyz (rad/s), accel xyz (m/s^2), finite.
std::vector<sensor::ImuSample> ImuRows(const py::handle& obj, const char* who);

// A view (no copy) of an (H, W) uint8 array whose rows are contiguous; the array must stay alive
// while the view is used.
cv::Mat GrayImageView(const py::array& image, const char* who);

// A frame's observations: points (N, 3) rows (track id, u, v); segments (M, 5) rows
// (track id, start u, v, end u, v); undistorted pixels; None: none. `frame`: the index given.
window::FrameInput FrameArg(double t, const py::handle& points, const py::handle& segments,
                            int frame, const char* who);

py::dict WindowDict(const window::WindowFrameResult& r);

// f() with the GIL released and `mutex` held: the lock is taken without the GIL and given back
// before the GIL is taken again (no deadlock with a thread that holds the GIL and waits for it).
template <typename F>
auto WithoutGil(std::mutex& mutex, F&& f) {
  py::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(mutex);
  return f();
}

// f() with `mutex` held (the GIL kept: short calls).
template <typename F>
auto Locked(std::mutex& mutex, F&& f) {
  std::lock_guard<std::mutex> lock(mutex);
  return f();
}

// A finite time, or ValueError naming `who`.
double TimeArg(const py::handle& t, const char* who);

}  // namespace python
}  // namespace plucker
