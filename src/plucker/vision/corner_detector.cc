#include "plucker/vision/corner_detector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace plucker {
namespace vision {
namespace {

// Reflect-101 row index.
int Reflect(int y, int h) { return y < 0 ? -y : (y >= h ? 2 * h - 2 - y : y); }

// The three gradient products of row y (float, as OpenCV's), padded by one reflected column
// each side, then their 3-wide sums in double ((a + b) + c, OpenCV's RowSum order).
class RowSums {
 public:
  RowSums(const cv::Mat& dx, const cv::Mat& dy)
      : dx_(dx), dy_(dy), w_(dx.cols), products_(3 * static_cast<size_t>(w_ + 2)) {}

  void operator()(int y, double* out0, double* out1, double* out2) {
    y = Reflect(y, dx_.rows);
    const float* __restrict px = dx_.ptr<float>(y);
    const float* __restrict py = dy_.ptr<float>(y);
    float* xx = products_.data();
    float* xy = xx + (w_ + 2);
    float* yy = xy + (w_ + 2);
    float* __restrict a0 = xx + 1;
    float* __restrict a1 = xy + 1;
    float* __restrict a2 = yy + 1;
    for (int x = 0; x < w_; ++x) {
      const float gx = px[x], gy = py[x];
      a0[x] = gx * gx;
      a1[x] = gx * gy;
      a2[x] = gy * gy;
    }
    for (float* p : {xx, xy, yy}) {
      p[0] = p[2];
      p[w_ + 1] = p[w_ - 1];
    }
    Sum3(xx, out0);
    Sum3(xy, out1);
    Sum3(yy, out2);
  }

 private:
  void Sum3(const float* __restrict in, double* __restrict out) const {
    for (int x = 0; x < w_; ++x) {
      out[x] = (static_cast<double>(in[x]) + static_cast<double>(in[x + 1])) +
               static_cast<double>(in[x + 2]);
    }
  }

  const cv::Mat& dx_;
  const cv::Mat& dy_;
  int w_;
  std::vector<float> products_;
};

// The eigenvalue of columns [x0, x1) from the three box sums (float, as OpenCV's).
void MinEigen(const float* __restrict bxx, const float* __restrict bxy, const float* __restrict byy,
              int x0, int x1, float* __restrict e) {
  for (int x = x0; x < x1; ++x) {
    const float a = bxx[x] * 0.5f, b = bxy[x], c = byy[x] * 0.5f;
    const float t = a - c;
    e[x] = (a + c) - std::sqrt(t * t + b * b);
  }
}

}  // namespace

void MinEigenResponse3(const cv::Mat& image, cv::Mat* response, const cv::Mat& needed) {
  if (image.empty() || image.type() != CV_8UC1) {
    throw std::invalid_argument("MinEigenResponse3: the image must be non-empty 8-bit grayscale");
  }
  if (!needed.empty() && (needed.type() != CV_8UC1 || needed.size() != image.size())) {
    throw std::invalid_argument("MinEigenResponse3: `needed` must be 8-bit of the image's size");
  }
  const int w = image.cols, h = image.rows;
  // cornerMinEigenVal's scale for an 8-bit image, 3x3 Sobel and 3x3 block: 1 / (4 * 3 * 255).
  const double scale = 1.0 / (4.0 * 3.0 * 255.0);
  cv::Mat dx, dy;
  cv::Sobel(image, dx, CV_32F, 1, 0, 3, scale, 0, cv::BORDER_DEFAULT);
  cv::Sobel(image, dy, CV_32F, 0, 1, 3, scale, 0, cv::BORDER_DEFAULT);
  RowSums row_sums(dx, dy);
  // Per product: a ring of three row sums (slot (r + 1) % 3 holds row r) and the running
  // column sum (OpenCV's ColumnSum: sum += new row, out = sum, sum -= oldest row).
  std::vector<double> buffer(12 * static_cast<size_t>(w));
  auto row = [&](int slot, int k) { return &buffer[(static_cast<size_t>(slot) * 3 + k) * w]; };
  auto fill = [&](int r) {
    const int s = (r + 1) % 3;
    row_sums(r, row(s, 0), row(s, 1), row(s, 2));
  };
  fill(-1);
  fill(0);
  for (int k = 0; k < 3; ++k) {
    double* __restrict sum = row(3, k);
    const double* __restrict r0 = row(0, k);
    const double* __restrict r1 = row(1, k);
    for (int x = 0; x < w; ++x) sum[x] = (0.0 + r0[x]) + r1[x];
  }
  response->create(h, w, CV_32F);
  std::vector<float> box(3 * static_cast<size_t>(w));
  for (int y = 0; y < h; ++y) {
    fill(y + 1);
    const int oldest = y % 3, newest = (y + 2) % 3;
    for (int k = 0; k < 3; ++k) {
      double* __restrict sum = row(3, k);
      const double* __restrict add = row(newest, k);
      const double* __restrict sub = row(oldest, k);
      float* __restrict out = &box[static_cast<size_t>(k) * w];
      for (int x = 0; x < w; ++x) {
        const double s = sum[x] + add[x];
        out[x] = static_cast<float>(s);
        sum[x] = s - sub[x];
      }
    }
    const float* __restrict bxx = &box[0];
    const float* __restrict bxy = &box[w];
    const float* __restrict byy = &box[2 * static_cast<size_t>(w)];
    float* __restrict e = response->ptr<float>(y);
    if (needed.empty()) {
      MinEigen(bxx, bxy, byy, 0, w, e);
      continue;
    }
    // Runs of needed pixels; 0 between them.
    const uchar* m = needed.ptr<uchar>(y);
    for (int x = 0; x < w;) {
      const int begin = x;
      while (x < w && !m[x]) ++x;
      std::fill(e + begin, e + x, 0.0f);
      const int run = x;
      while (x < w && m[x]) ++x;
      MinEigen(bxx, bxy, byy, run, x, e);
    }
  }
}

std::vector<cv::Point2f> ShiTomasiCorners(const cv::Mat& image, int max_corners,
                                          double quality_level, double min_distance,
                                          const cv::Mat& mask) {
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != image.size())) {
    throw std::invalid_argument("ShiTomasiCorners: the mask must be 8-bit of the image's size");
  }
  if (!(quality_level > 0 && quality_level < 1)) {
    throw std::invalid_argument("ShiTomasiCorners: quality_level must be in (0, 1)");
  }
  // Only the mask's pixels and their 3x3 neighbours are read below: the eigenvalue elsewhere
  // is skipped (the same corners).
  cv::Mat needed;
  if (!mask.empty()) cv::dilate(mask, needed, cv::Mat());
  cv::Mat eig;
  MinEigenResponse3(image, &eig, needed);
  double max_value = 0;
  cv::minMaxLoc(eig, nullptr, &max_value, nullptr, nullptr, mask);
  const float threshold = static_cast<float>(max_value * quality_level);
  auto kept = [threshold](float v) { return v > threshold ? v : 0.0f; };  // THRESH_TOZERO
  // Candidates: non-zero local maxima (3x3, of the thresholded response) inside the mask,
  // in raster order, as pointers into eig (the sort's tie order is by address).
  std::vector<const float*> candidates;
  for (int y = 1; y < image.rows - 1; ++y) {
    const float* up = eig.ptr<float>(y - 1);
    const float* mid = eig.ptr<float>(y);
    const float* down = eig.ptr<float>(y + 1);
    const uchar* m = mask.empty() ? nullptr : mask.ptr<uchar>(y);
    for (int x = 1; x < image.cols - 1; ++x) {
      if (m && !m[x]) continue;
      const float v = kept(mid[x]);
      if (v == 0) continue;
      float best = v;
      for (int d = -1; d <= 1; ++d) {
        best = std::max({best, kept(up[x + d]), kept(down[x + d])});
        if (d != 0) best = std::max(best, kept(mid[x + d]));
      }
      if (v == best) candidates.push_back(mid + x);
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const float* a, const float* b) {
    return (*a > *b) ? true : (*a < *b) ? false : (a > b);
  });
  std::vector<cv::Point2f> corners;
  auto position = [&](const float* p) {
    const std::ptrdiff_t offset = reinterpret_cast<const uchar*>(p) - eig.ptr();
    const int y = static_cast<int>(offset / eig.step);
    const int x = static_cast<int>((offset - y * eig.step) / sizeof(float));
    return cv::Point2f(static_cast<float>(x), static_cast<float>(y));
  };
  if (min_distance < 1) {
    for (const float* p : candidates) {
      corners.push_back(position(p));
      if (max_corners > 0 && static_cast<int>(corners.size()) == max_corners) break;
    }
    return corners;
  }
  // Minimum distance on a grid of cells of min_distance px (each cell's accepted corners).
  const int cell = cvRound(min_distance);
  const int gw = (image.cols + cell - 1) / cell, gh = (image.rows + cell - 1) / cell;
  std::vector<std::vector<cv::Point2f>> grid(static_cast<size_t>(gw) * gh);
  const double min_d2 = min_distance * min_distance;
  for (const float* p : candidates) {
    const cv::Point2f c = position(p);
    const int cx = static_cast<int>(c.x) / cell, cy = static_cast<int>(c.y) / cell;
    bool good = true;
    for (int yy = std::max(0, cy - 1); good && yy <= std::min(gh - 1, cy + 1); ++yy) {
      for (int xx = std::max(0, cx - 1); good && xx <= std::min(gw - 1, cx + 1); ++xx) {
        for (const cv::Point2f& q : grid[static_cast<size_t>(yy) * gw + xx]) {
          const float dx = c.x - q.x, dy = c.y - q.y;
          if (dx * dx + dy * dy < min_d2) {
            good = false;
            break;
          }
        }
      }
    }
    if (!good) continue;
    grid[static_cast<size_t>(cy) * gw + cx].push_back(c);
    corners.push_back(c);
    if (max_corners > 0 && static_cast<int>(corners.size()) == max_corners) break;
  }
  return corners;
}

}  // namespace vision
}  // namespace plucker
