#include "SyntheticCameraOut.h"

#include "Core/Error.h"
#include "SyntheticHaze.h"
#include "SyntheticRandom.h"

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>

namespace tissuemosaic::synthetic {

namespace {
constexpr double pi = 3.141592653589793;
}

SyntheticCameraOut::SyntheticCameraOut(int start, int end, uint32_t seed) : start_(start), end_(end), seed_(seed) {
  require(start < 0 || end > start, "camera-out: the span [start, end) is empty");
}

Eigen::Matrix4d SyntheticCameraOut::returnMotion() const {
  std::mt19937 generator(seed_ ^ 0xbac4u);
  // Sideways (in the image plane) with a little along the optical axis.
  const double direction = uniform(generator, 0, 2 * pi);
  const Eigen::Vector3d offset =
      Eigen::Vector3d(std::cos(direction), std::sin(direction), uniform(generator, -0.3, 0.3)).normalized() *
      kReturnOffsetMm;
  // Mostly a roll about the optical axis, a little tilt: a returned scope still faces the tissue.
  const double tiltDirection = uniform(generator, 0, 2 * pi);
  const double tiltShare = uniform(generator, 0.3, 0.5);
  const Eigen::Vector3d axis = Eigen::Vector3d(tiltShare * std::cos(tiltDirection), tiltShare * std::sin(tiltDirection),
                                               uniform(generator, 0, 1) < 0.5 ? -1.0 : 1.0)
                                   .normalized();
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(kReturnRotationDeg * pi / 180.0, axis).toRotationMatrix();
  T.block<3, 1>(0, 3) = offset;
  return T;
}

void SyntheticCameraOut::render(int index, cv::Size size, double fps, double noiseStdGrey, cv::Mat& left,
                                cv::Mat& right) const {
  require(contains(index), "camera-out: frame " + std::to_string(index) + " is not out of the body");
  const double phase = static_cast<double>(index - start_) / (end_ - start_);
  const double timeS = index / fps;
  for (int eye = 0; eye < 2; ++eye) {
    cv::Mat& image = eye == 0 ? left : right;
    image.create(size, CV_8UC3);
    if (phase < 1.0 / 3) {
      // Smoke filling the view as the scope pulls back: a dim reddish glow under thick, churning haze.
      image.setTo(cv::Scalar(25, 30, 70));
      const cv::Mat density = hazeDensity(size, 3 * timeS, seed_ + 17u * eye);
      applyHaze(image, density, 0.9, cv::Vec3d(150, 160, 175));
    } else if (phase < 2.0 / 3) {
      image.setTo(cv::Scalar(6, 6, 8));  // inside the trocar: dark
    } else {
      // A smeared lens being wiped: bright, defocused blobs of tissue colour drifting across.
      image.setTo(cv::Scalar(60, 70, 150));
      std::mt19937 generator(static_cast<uint32_t>(seed_ ^ (0x51e0u + 131u * static_cast<uint32_t>(index) + eye)));
      for (int blob = 0; blob < 5; ++blob) {
        const cv::Point centre(static_cast<int>(uniform(generator, 0, size.width)),
                               static_cast<int>(uniform(generator, 0, size.height)));
        const int radius = static_cast<int>(uniform(generator, 0.1, 0.3) * size.width);
        const cv::Scalar colour(uniform(generator, 120, 200), uniform(generator, 130, 210), uniform(generator, 200, 250));
        cv::circle(image, centre, radius, colour, cv::FILLED, cv::LINE_AA);
      }
      const double sigma = 0.05 * size.width;
      cv::GaussianBlur(image, image, cv::Size(), sigma, sigma);
    }
    // Sensor noise, its own stream per frame and eye.
    for (int y = 0; y < size.height; ++y) {
      cv::Vec3b* row = image.ptr<cv::Vec3b>(y);
      for (int x = 0; x < size.width; ++x) {
        const uint64_t pixel = static_cast<uint64_t>(y) * size.width + x;
        for (int c = 0; c < 3; ++c) {
          const double noisy = row[x][c] + noiseStdGrey * hashedGaussian(seed_, 0x7000000u + 2u * index + eye, pixel * 3 + c);
          row[x][c] = cv::saturate_cast<uchar>(noisy);
        }
      }
    }
  }
}

}  // namespace tissuemosaic::synthetic
