#include "image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include <png.h>

namespace rt {

std::vector<uint8_t> Image::rgb8() const {
    std::vector<uint8_t> out(pixels.size() * 3);
    for (size_t i = 0; i < pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double v = std::clamp(pixels[i][c], 0.0, 1.0);
            out[3 * i + c] = uint8_t(std::floor(v * 255.0 + 0.5));
        }
    return out;
}

bool Image::operator==(const Image& o) const {
    return width == o.width && height == o.height &&
           std::memcmp(pixels.data(), o.pixels.data(), pixels.size() * sizeof(Vec3)) == 0;
}

namespace {
// splitmix64's finaliser: a well-mixed 64-bit hash step.
uint64_t mix(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
uint64_t bitsOf(double d) {
    uint64_t b;
    std::memcpy(&b, &d, sizeof b);
    return b;
}
}  // namespace

uint64_t contributionDigest(const Contribution& c) {
    uint64_t h = mix(c.pixel);
    for (uint64_t v : {c.key.path, uint64_t(c.key.slot), bitsOf(c.rgb.x), bitsOf(c.rgb.y), bitsOf(c.rgb.z)}) h = mix(h ^ v);
    return h;
}

void writePng(const Image& image, const std::string& path) {
    std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        throw std::runtime_error(path + ": libpng initialisation failed");
    }
    const std::vector<uint8_t> rgb = image.rgb8();
    std::vector<png_bytep> rows(image.height);
    for (int y = 0; y < image.height; ++y) rows[y] = const_cast<png_bytep>(rgb.data() + size_t(y) * image.width * 3);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        throw std::runtime_error(path + ": writing PNG failed");
    }
    png_init_io(png, f.get());
    png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (std::fflush(f.get()) != 0) throw std::runtime_error(path + ": writing PNG failed");
}

}  // namespace rt
