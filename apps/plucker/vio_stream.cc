#include "vio_stream.h"

#include <deque>

#include "plucker/bag/bag_reader.h"
#include "plucker/io/euroc_dataset.h"
#include "plucker/io/io_error.h"

namespace plucker {
namespace app {
namespace {

class FolderVioStream : public VioStream {
 public:
  explicit FolderVioStream(const VioInput& in) : in_(in) {}
  std::size_t frames() const override {
    return in_.images.empty() ? in_.frames.size() : in_.images.size();
  }
  bool Next(VioItem* item) override {
    *item = VioItem();
    const std::size_t n = frames();
    const double t = next_frame_ < n ? FrameTime(next_frame_) : 0.0;
    // A driver delivers the IMU up to the image's timestamp before the image.
    if (next_imu_ < in_.imu.size() &&
        (next_frame_ >= n || next_imu_ == 0 || in_.imu[next_imu_ - 1].t < t)) {
      item->is_imu = true;
      item->imu = in_.imu[next_imu_++];
      return true;
    }
    if (next_frame_ >= n) return false;
    item->frame = next_frame_++;
    item->t = t;
    if (!in_.images.empty()) item->name = in_.images[item->frame].image;
    return true;
  }

 private:
  double FrameTime(std::size_t i) const {
    return in_.images.empty() ? in_.frames[i].time : in_.images[i].t;
  }
  const VioInput& in_;
  std::size_t next_imu_ = 0, next_frame_ = 0;
};

class BagVioStream : public VioStream {
 public:
  BagVioStream(std::unique_ptr<BagSensorStream> bag, std::int64_t origin_ns, double shift_s)
      : bag_(std::move(bag)), origin_ns_(origin_ns), shift_s_(shift_s) {}
  std::size_t frames() const override { return bag_->image_messages(); }
  std::vector<std::string> warnings() const override { return bag_->warnings(); }

  bool Next(VioItem* item) override {
    for (;;) {
      // A held frame goes once the IMU has reached it (or the bag has ended).
      if (!held_.empty() && (ended_ || (has_imu_ && last_imu_t_ >= held_.front().t))) {
        *item = std::move(held_.front());
        held_.pop_front();
        return true;
      }
      if (ended_) return false;
      BagItem m;
      if (!bag_->Next(&m)) {
        ended_ = true;
        continue;
      }
      *item = VioItem();
      item->is_imu = m.is_imu;
      const double t = static_cast<double>(m.stamp_ns - origin_ns_) * 1e-9;
      if (m.is_imu) {
        item->imu = m.imu;
        item->imu.t = last_imu_t_ = t;
        has_imu_ = true;
        return true;
      }
      item->t = t + shift_s_;
      item->name = std::move(m.name);
      item->image = std::move(m.image);
      item->problem = std::move(m.problem);
      held_.push_back(std::move(*item));
    }
  }

 private:
  std::unique_ptr<BagSensorStream> bag_;
  std::int64_t origin_ns_;
  double shift_s_;
  std::deque<VioItem> held_;  // frames the IMU has not reached yet (a few)
  bool ended_ = false, has_imu_ = false;
  double last_imu_t_ = 0.0;
};

void SetCalibration(const CameraCalibration& calib, VioInput* in) {
  if (calib.has_camera) {
    in->calibration.camera = calib.camera;
    in->calibration.T_b_c = calib.RequireT_b_c();
  }
  if (calib.imu) in->calibration.imu = *calib.imu;
}

}  // namespace

std::unique_ptr<VioStream> MakeFolderVioStream(const VioInput& in) {
  return std::make_unique<FolderVioStream>(in);
}

std::unique_ptr<VioStream> OpenVioBag(const VioBagSource& s, const CameraCalibration& calib,
                                      VioInput* in) {
  if (s.image_topic.empty() || s.imu_topic.empty())
    throw std::invalid_argument("--bag needs --image-topic T and --imu-topic T");
  if (!calib.imu) {
    throw std::invalid_argument(
        "--bag needs the IMU noise model: --imu-sensor imu0/sensor.yaml or --imu-calib imu.yaml");
  }
  SetCalibration(calib, in);
  auto bag = std::make_unique<BagSensorStream>(s.bag, s.image_topic, s.imu_topic, s.stamp);
  const std::optional<std::int64_t> origin = bag->FirstStampNs(s.imu_topic);
  if (!origin) throw io::IoError(s.bag, "topic " + s.imu_topic + ": no readable IMU message");
  in->source = s.bag;
  in->clock_origin_ns = *origin;
  return std::make_unique<BagVioStream>(std::move(bag), *origin, calib.timeshift_cam_imu);
}

void CheckVioSources(const std::string& features, const std::string& euroc, const VioBagSource& bag,
                     const CameraFlags& c) {
  if (!features.empty() + !euroc.empty() + !bag.bag.empty() != 1)
    throw std::invalid_argument("give --features DIR, --euroc DIR or --bag FILE");
  if (!features.empty() && (HasCameraFlag(c) || !c.imu_sensor.empty() || !c.imu_calib.empty())) {
    throw std::invalid_argument(
        "--sensor, --calib, --imu-sensor, --imu-calib apply to --euroc and --bag (a features "
        "folder has its rig.txt)");
  }
}

void ReplaceVioCalibration(const CameraCalibration& calib, VioInput* in) {
  SetCalibration(calib, in);
  if (calib.timeshift_cam_imu == 0.0 || in->images.empty()) return;
  for (io::EurocFrame& f : in->images) f.t += calib.timeshift_cam_imu;
  std::vector<io::FrameSkip> skipped;
  std::vector<std::string> warnings;
  io::CheckImuCoverage(in->imu, {}, in->source + ": cam0/data.csv", in->source + ": imu0/data.csv",
                       &in->images, &skipped, &warnings);
  for (std::string& w : SkipWarnings(skipped, " (the frame time moved by timeshift_cam_imu " +
                                                  std::to_string(calib.timeshift_cam_imu) +
                                                  " s of " + calib.source + ")")) {
    in->warnings.push_back(std::move(w));
  }
  in->skipped_input_frames += static_cast<int>(skipped.size());
}

std::unique_ptr<VioStream> OpenVioInput(const std::string& features, const std::string& euroc,
                                        const VioBagSource& bag, const CameraFlags& camera,
                                        int point_stride, VioInput* in) {
  if (!bag.bag.empty()) return OpenVioBag(bag, ReadCameraCalibration(camera), in);
  *in = euroc.empty() ? ReadVioFeatures(features, point_stride) : ReadVioEuroc(euroc);
  if (!euroc.empty()) ReplaceVioCalibration(ReadCameraCalibration(camera, 0, 0, false), in);
  return MakeFolderVioStream(*in);
}

}  // namespace app
}  // namespace plucker
