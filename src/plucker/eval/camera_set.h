// Accuracy of a reconstructed set of cameras (structure from motion) against ground-truth
// cameras: the estimate's camera centres are aligned to the ground truth by Umeyama (Sim(3) by
// default: a monocular reconstruction has an arbitrary scale), then per camera the centre error
// |c_gt - S c_est| and the rotation error angle(R_gt^T R R_est) are measured. The rotation R of
// the centre alignment is uncertain by about (centre noise / extent of the centres): with mm-level
// ground truth over a few metres that is a few hundredths of a degree, the size of the errors to
// measure. So the rotation error is also given (rotation_error_deg, the headline figure) after
// the rotation that best fits the orientations themselves, R_o = the chordal mean of
// R_gt_i R_est_i^T (projected onto SO(3) by SVD); the error of R from the centres is
// rotation_error_centres_deg. Cameras missing in
// the estimate (not registered) are counted, not aligned.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "plucker/eval/alignment.h"
#include "plucker/geometry/se3.h"

namespace plucker {
namespace eval {

struct CameraSetErrors {
  bool ok = false;
  std::string message;  // why not, when !ok
  int cameras = 0;      // in the ground truth
  int registered = 0;   // present in the estimate (and compared)
  std::vector<int> missing;
  std::vector<double> centre_error;        // per compared camera, ground-truth units
  std::vector<double> rotation_error_deg;  // per compared camera, orientations aligned by R_o
  std::vector<double> rotation_error_centres_deg;  // orientations aligned by the centres' R
  double median_centre = 0.0, max_centre = 0.0;
  double median_rotation_deg = 0.0, max_rotation_deg = 0.0;
  double median_rotation_centres_deg = 0.0, max_rotation_centres_deg = 0.0;
  double scale = 1.0;  // of the alignment
};

// est[i] and gt[i] are T_w_c of camera i (the sizes must agree). Needs 3 registered cameras.
CameraSetErrors CompareCameraSets(const std::vector<std::optional<SE3d>>& est,
                                  const std::vector<SE3d>& gt,
                                  AlignmentMode mode = AlignmentMode::kSim3);

}  // namespace eval
}  // namespace plucker
