#include "camera.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace rt {

Camera::Camera(const View& v, int width, int height) : eye_(v.from), width_(width), height_(height) {
    forward_ = glm::normalize(v.at - v.from);
    right_ = glm::normalize(glm::cross(forward_, v.up));  // up need not be unit or orthogonal
    up_ = glm::cross(right_, forward_);
    const double halfWidth = std::tan(v.angle * M_PI / 360.0);
    spacing_ = width > 1 ? 2.0 * halfWidth / (width - 1) : 0.0;
}

Ray Camera::primaryRay(int x, int y) const {
    const double u = (x - 0.5 * (width_ - 1)) * spacing_;
    const double v = (0.5 * (height_ - 1) - y) * spacing_;
    return Ray(eye_, glm::normalize(forward_ + u * right_ + v * up_));
}

}  // namespace rt
