// The camera + IMU sequence folder format (docs/sim-format.md), read into and written from
// sensor::CameraImuSequence: the simulator's output (sim::ToCameraImuSequence) and the input of
// users who bring their own front end. Plain text, one record a line, '#' comments, numbers
// written with %.17g so that every double reads back bit-exactly.
//   rig.txt            image size, intrinsics, T_b_c, IMU and observation noise models
//   frames.txt         `t`, the time of each frame
//   imu.txt            `t gx gy gz ax ay az [bgx bgy bgz bax bay baz]` (biases: ground truth)
//   points.txt         `frame point_id u v` (ids: track ids; -1 outlier)
//   segments.txt       `frame line_id su sv eu ev`
// Ground truth, all three or none:
//   scene.txt          kind, free space, planes, points (with their plane), segments
//   trajectory.txt     TUM rows `t tx ty tz qx qy qz qw` of T_w_c (one per frame)
//   body_states.txt    `t tx ty tz qx qy qz qw vx vy vz` of T_w_b and v_w (one per frame)
// The reader validates everything (field counts, numbers, finiteness, unit quaternions, ids and
// frames in range, increasing times) and throws io::IoError naming the file and the line.
#pragma once

#include <string>
#include <vector>

#include "plucker/io/io_error.h"
#include "plucker/sensor/camera_imu_sequence.h"

namespace plucker {
namespace io {

// The file names of the format, in writing order.
const std::vector<std::string>& CameraImuSequenceFileNames();

// Writes the folder (created if needed) with io::WriteFileAtomically; the ground-truth files only
// when the sequence has it (without, those of a previous sequence in `dir` are removed). Throws
// IoError for inconsistent sizes and non-finite values.
void WriteCameraImuSequence(const std::string& dir, const sensor::CameraImuSequence& sequence);

// Reads and validates a folder of this format, with or without ground truth (folders written
// before frames.txt existed take the frame times from trajectory.txt). Throws IoError.
sensor::CameraImuSequence ReadCameraImuSequence(const std::string& dir);

// True when `dir` does not exist, is an empty folder, or holds only files of this format
// (a previous simulation, whose rig.txt starts with the format's header). Otherwise false, with
// the reason (e.g. the first foreign file) in *why. Never modifies anything.
bool IsSafeToWriteCameraImuSequence(const std::string& dir, std::string* why = nullptr);

}  // namespace io
}  // namespace plucker
