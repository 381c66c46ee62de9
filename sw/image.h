// A rendered frame: one linear RGB value (double) per pixel, each the sum of
// its contributions (PixelSums, pixel_sum.h: the same whatever their order).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "ray_job.h"

namespace rt {

struct Image {
    int width = 0, height = 0;
    std::vector<Vec3> pixels;

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(size_t(w) * h, Vec3(0.0)) {}
    // 8-bit RGB, clamped to [0, 1], rounded to nearest.
    std::vector<uint8_t> rgb8() const;
    bool operator==(const Image& o) const;  // bit-identical doubles
};

// An order-independent fingerprint of a set of contributions: the sum
// (mod 2^64) of a hash of each one's pixel, path key and colour bits. Two
// sets with the same digest and count are, but for a 2^-64 chance, the same
// multiset: a frame buffer that lost, doubled or changed one would show it.
uint64_t contributionDigest(const Contribution& c);

// Writes an 8-bit RGB PNG; throws std::runtime_error naming the file.
void writePng(const Image& image, const std::string& path);

}  // namespace rt
