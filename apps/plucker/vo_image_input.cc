#include "vo_image_input.h"

#include "plucker/io/image_folder.h"
#include "plucker/io/io_error.h"

namespace plucker {
namespace app {
namespace {

// The image, or an empty one with the reason it cannot be used.
cv::Mat Checked(cv::Mat image, const std::string& name, const sensor::Camera& camera,
                std::string* problem) {
  if (image.empty() || (image.cols == camera.width && image.rows == camera.height)) return image;
  *problem = name + ": image size " + std::to_string(image.cols) + "x" +
             std::to_string(image.rows) + " differs from the calibration's " +
             std::to_string(camera.width) + "x" + std::to_string(camera.height);
  return {};
}

}  // namespace

void CheckVoSources(const std::string& features, const VoImageSource& im, const std::string& draw) {
  if (!features.empty() + !im.images.empty() + !im.bag.bag.empty() != 1)
    throw std::invalid_argument("give --features DIR, --images DIR or --bag FILE");
  if (features.empty() && !HasCameraFlag(im.camera)) {
    throw std::invalid_argument(std::string(im.bag.bag.empty() ? "--images" : "--bag") +
                                " needs --calib calib.txt|camchain.yaml or --sensor sensor.yaml");
  }
  if (!features.empty() && HasCameraFlag(im.camera))
    throw std::invalid_argument("--sensor, --calib apply to --images and --bag");
  if (im.images.empty() && !draw.empty())
    throw std::invalid_argument("--draw needs --images (it reads the image files)");
}

VoImageStream::VoImageStream(const VoImageSource& s) : rate_hz_(s.frame_rate_hz) {
  int width = 0, height = 0;
  if (!s.bag.bag.empty()) {
    const BagFlags& b = s.bag;
    if (b.image_topic.empty()) throw std::invalid_argument("--bag needs --image-topic T");
    source_ = b.bag;
    bag_ = std::make_unique<BagSensorStream>(b.bag, b.image_topic, "", b.stamp);
    BagItem item;
    if (!bag_->Next(&item))
      throw io::IoError(b.bag, "topic " + b.image_topic + ": no readable image message");
    first_ns_ = item.stamp_ns;
    width = item.image.cols, height = item.image.rows;
    first_ = VoImage{0.0, std::move(item.image), std::move(item.name), std::move(item.problem)};
  } else {
    source_ = s.images;
    files_ = io::ListImageFiles(s.images);
    if (s.camera.sensor.empty()) {  // KITTI's calib.txt has no size: the first image's
      const cv::Mat first = io::ReadGrayImage(files_.front());
      width = first.cols, height = first.rows;
    }
  }
  camera_ = ReadCameraCalibration(s.camera, width, height).camera;
}

VoImageStream::~VoImageStream() = default;

std::size_t VoImageStream::size() const { return bag_ ? bag_->image_messages() : files_.size(); }

bool VoImageStream::Next(VoImage* out) {
  *out = VoImage();
  if (bag_) {
    if (first_) {
      *out = std::move(*first_);
      first_.reset();
    } else {
      BagItem item;
      if (!bag_->Next(&item)) return false;
      out->t = static_cast<double>(item.stamp_ns - first_ns_) * 1e-9;
      out->image = std::move(item.image), out->name = std::move(item.name);
      out->problem = std::move(item.problem);
    }
    out->image = Checked(out->image, out->name, camera_, &out->problem);
    return true;
  }
  if (next_ >= files_.size()) return false;
  out->t = double(next_) / rate_hz_;
  out->name = files_[next_++];
  try {
    out->image = Checked(io::ReadGrayImage(out->name), out->name, camera_, &out->problem);
  } catch (const io::IoError& e) {
    out->problem = e.what();
  }
  return true;
}

std::vector<std::string> VoImageStream::warnings() const {
  return bag_ ? bag_->warnings() : std::vector<std::string>{};
}

}  // namespace app
}  // namespace plucker
