// Monocular point + line visual odometry as an online pipeline: one frame in, one result out.
//   AddImage     the image front end (vision/image_frontend.h; undistorted first when the camera
//                has distortion) turns the image into point and segment tracks, then AddFrame;
//   AddFrame     features given (as from a features folder, docs/sim-format.md):
//     start      while there is no map, frames are buffered and the start search of first view a
//                (monocular_initializer.h) tests each new frame's pair with a as it arrives: pairs
//                in order, the first start accepted ends it at that frame; widest pair first
//                (features folders' default), it waits for the frames up to a + max_init_gap.
//                No start from a: a + 1 is searched. A start localises the buffered frames
//                before its second view b against the new map and tracks those after b at once;
//     track      window AddFrame (window/sliding_window_estimator.h): predict, track with the PnP
//                fallback, keyframe decision, triangulate, solve, marginalize;
//     restart    after max_lost_frames lost frames in a row, a new start from the next frame,
//                its scale chained to the old map (the last frames' speed times the pair's gap).
//   Finish       the end of the sequence: the start search on the frames buffered so far.
// Causality: the result AddImage/AddFrame return for frame k uses only the inputs of frames
// 0 .. k (feeding a prefix of a sequence gives the same results for its frames: tested). The
// cost is latency at a start: frames buffered while the start is searched get no pose online
// (status kInitializing), up to max_init_gap frames with the widest-first order.
// Trajectory() is the refined view after Finish: the frames before a start backfilled with their
// localisation against that map (what `plucker vo --out` writes); it is the same trajectory the
// batch program wrote before this class existed. No I/O, no clock (stages go to observers).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/odometry/frame_observer.h"
#include "plucker/odometry/monocular_initializer.h"
#include "plucker/sensor/camera.h"
#include "plucker/vision/image_frontend.h"
#include "plucker/vision/undistort.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace odometry {

struct MonocularOdometryOptions {
  window::SlidingWindowOptions window;
  // AddImage only; segments are tracked when frontend.use_lines and window.use_lines.
  vision::ImageFrontendOptions frontend;
  MonocularStartOptions start;
  int max_lost_frames = 3;  // lost frames in a row before a new start (re-initialisation)
  // Stereo (window.T_c0_c1 set; FrameInput::right_points, right_segments): a start is one
  // frame's left-right pairs, triangulated at once (metric scale, no two-view search, `start`
  // unused), with at least this many landmarks; a restart is put where the previous map's last
  // motion leads (no scale to chain).
  int min_stereo_landmarks = 20;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

enum class MonocularStatus {
  kInitializing,   // no map (first start, or a new one after a loss): buffered, no pose
  kInitialized,    // the first start was found at this frame
  kReinitialized,  // a later start was found at this frame (scale chained)
  kTracking,       // tracked by the window
  kLost,           // the window could not track it (T_w_c: the prediction or the last pose)
};
const char* ToString(MonocularStatus status);

// The online result of one frame: what is known when the frame arrives.
struct MonocularFrameResult {
  int frame = 0;  // 0, 1, ... in the order given
  double time = 0.0;
  MonocularStatus status = MonocularStatus::kInitializing;
  bool has_pose = false;  // T_w_c localised (else the last pose known, identity before any)
  SE3d T_w_c;
  std::optional<window::WindowFrameResult> window;  // the window's statistics if tracked now
  int observed_points = 0;                          // the frame's input
  int observed_segments = 0;
  int caught_up_frames = 0;  // earlier buffered frames tracked in this call (after a start)
};

// The refined view of one frame (Trajectory()).
enum class MonocularPoseSource {
  kNotLocalized,           // no pose: the last pose known (or the map's first view's)
  kInitialization,         // a keyframe of a start
  kLocalizedBeforeWindow,  // buffered during a start search, localised against its map
  kTracked,
  kLost,
};
const char* ToString(MonocularPoseSource source);

struct MonocularFrameRecord {
  double time = 0.0;
  MonocularPoseSource source = MonocularPoseSource::kNotLocalized;
  bool has_pose = false;
  SE3d T_w_c;
  bool keyframe = false;
  int map = -1;  // index into Maps()
  std::optional<window::WindowFrameResult> window;
};

// One start (the first map, or a re-initialisation).
struct MonocularMap {
  int first = 0, second = 0;               // the two views a and b
  std::vector<int> keyframes;              // of the start, oldest first
  int after_lost_frame = -1;               // the last frame before the search (-1: the first map)
  std::optional<double> chained_baseline;  // |t_ab| chained to the previous map (else 1)
  int points = 0, lines = 0, tries = 0;
  double chi2_z = 0.0;
  bool stereo = false;  // a stereo start (first == second): metric, nothing chained
};

struct MonocularSummary {
  int frames = 0;
  int keyframes = 0;
  int lost_frames = 0;
  int pnp_recoveries = 0;
  int marginalized_keyframes = 0;
  int failed_marginalizations = 0;
  int window_frames = 0;  // window AddFrame calls
};

// Called for each frame once its pose of the refined view is set (after its tracking, or at a
// start for the frames up to b), with the map as it is then (frame_observer.h).
using MonocularFrameObserver = FrameObserver;

class MonocularOdometry {
 public:
  // K: the pinhole of the observations (AddFrame; AddImage takes undistorted images). camera:
  // AddImage undistorts into the camera's ideal pinhole (no distortion: images used as given).
  // Throws std::invalid_argument for invalid options or camera.
  MonocularOdometry(const PinholeIntrinsics& K, const MonocularOdometryOptions& options);
  MonocularOdometry(const sensor::Camera& camera, const MonocularOdometryOptions& options);
  ~MonocularOdometry();
  MonocularOdometry(const MonocularOdometry&) = delete;
  MonocularOdometry& operator=(const MonocularOdometry&) = delete;

  // The next image (8-bit gray, the camera's size): the front end, then AddFrame. An empty image
  // (one the caller could not read) is a frame without observations.
  MonocularFrameResult AddImage(double t, const cv::Mat& gray,
                                const vision::FrontendObserver& frontend_observer = {},
                                const window::StageObserver& window_observer = {});
  MonocularFrameResult AddFrame(window::FrameInput frame,
                                const window::StageObserver& window_observer = {});
  // The end of the input: a pending start search runs on the frames buffered.
  void Finish(const window::StageObserver& window_observer = {});

  void SetFrameObserver(MonocularFrameObserver observer);

  // The refined view (complete after Finish): one record per frame.
  const std::vector<MonocularFrameRecord>& Trajectory() const;
  const std::vector<MonocularMap>& Maps() const;
  const MonocularSummary& Summary() const;
  // After Finish: why no first start was found (empty when there is a map), and why the last
  // re-initialisation failed (its frames keep the last pose; empty when none failed).
  const std::string& StartFailure() const;
  const std::string& RestartFailure() const;
  int RestartFailedAfter() const;  // the frame after which it failed (-1: none)

  const PinholeIntrinsics& K() const;                 // of the observations
  const vision::Undistorter* undistorter() const;     // AddImage's, or nullptr
  const window::SlidingWindowEstimator* map() const;  // the current map, or nullptr

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace odometry
}  // namespace plucker
