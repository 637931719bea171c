// vio_euroc EUROC_DIR OUT.tum: the visual-inertial odometry of plucker on a EuRoC folder, fed as
// a driver would (the IMU up to each image's time, then the image), through the installed
// package alone; writes the refined trajectory, the file `plucker vio --euroc DIR --out OUT`.
#include <cstdio>
#include <stdexcept>

#include <plucker/io/euroc_dataset.h>
#include <plucker/io/image_folder.h>
#include <plucker/io/trajectory_io.h>
#include <plucker/odometry/visual_inertial_odometry.h>

int main(int argc, char** argv) {
  using namespace plucker;
  if (argc != 3) return std::fprintf(stderr, "usage: vio_euroc EUROC_DIR OUT.tum\n"), 2;
  try {
    const io::EurocDataset data = io::ReadEurocDataset(argv[1]);
    odometry::VisualInertialOdometry vio({},
                                         {data.cam0.camera, data.cam0.T_b_c, data.imu.imu_model});
    const std::vector<sensor::ImuSample>& imu = data.imu.imu;
    std::size_t k = 0;
    for (const io::EurocFrame& f : data.frames) {
      while (k < imu.size() && (k == 0 || imu[k - 1].t < f.t)) vio.AddImu(imu[k++]);
      try {
        vio.AddImage(f.t, io::ReadGrayImage(f.image));
      } catch (const std::exception& e) {  // unreadable: skipped, as `plucker vio` does
        std::fprintf(stderr, "vio_euroc: skipped %s: %s\n", f.image.c_str(), e.what());
      }
    }
    while (k < imu.size()) vio.AddImu(imu[k++]);
    const odometry::VioFrameResult end = vio.Finish();
    if (!vio.initialized()) throw std::runtime_error(end.message);
    std::vector<double> times;
    std::vector<SE3d> poses;
    for (const odometry::VioFrameRecord& r : vio.RefinedTrajectory()) {
      if (r.T_w_b) times.push_back(r.time), poses.push_back(*r.T_w_b);
    }
    // On the dataset's clock: the stamps of the EuRoC files, as `plucker vio` writes them.
    io::WriteTumTrajectoryOnClock(argv[2], data.imu.origin_ns, times, poses,
                                  {odometry::kRefinedTrajectoryNote});
    std::printf("vio_euroc: %s initialisation, %zu poses written to %s\n",
                vio.initialization().method.c_str(), poses.size(), argv[2]);
  } catch (const std::exception& e) {
    return std::fprintf(stderr, "vio_euroc: error: %s\n", e.what()), 1;
  }
  return 0;
}
