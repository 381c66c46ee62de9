// The NFF pinhole camera. `angle` is the full field of view between the
// centres of the outermost pixel columns; pixels are square, so the rows use
// the same spacing. Row 0 is the top of the image.
#pragma once
#include "ray.h"
#include "scene.h"

namespace rt {

class Camera {
public:
    Camera(const View& v, int width, int height);
    // Normalised primary ray through the centre of pixel (x, y).
    Ray primaryRay(int x, int y) const;
    int width() const { return width_; }
    int height() const { return height_; }

private:
    Vec3 eye_, forward_, right_, up_;
    double spacing_;  // distance between pixel centres on the plane at distance 1
    int width_, height_;
};

}  // namespace rt
