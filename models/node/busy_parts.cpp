#include "node/busy_parts.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace rt {

const char* busyKindName(int k) {
    static const char* const names[kBusyKinds] = {"test_sphere",  "test_polygon",  "test_cone",
                                                  "voxel_steps",  "ray_generation", "shading",
                                                  "send",         "receive",        "balancing_send",
                                                  "balancing_receive", "slab_rebuild"};
    static_assert(int(PrimitiveKind::Sphere) == 0 && int(PrimitiveKind::Polygon) == 1 && int(PrimitiveKind::Cone) == 2 &&
                  kPrimitiveKinds == 3, "the test_ names follow PrimitiveKind");
    if (k < 0 || k >= kBusyKinds) throw std::out_of_range("busyKindName");
    return names[k];
}

Picos sumOf(const BusyParts& p) { return std::accumulate(p.begin(), p.end(), Picos(0)); }

BusyParts& operator+=(BusyParts& a, const BusyParts& b) {
    for (int k = 0; k < kBusyKinds; ++k) a[size_t(k)] += b[size_t(k)];
    return a;
}

BusyParts& operator-=(BusyParts& a, const BusyParts& b) {
    for (int k = 0; k < kBusyKinds; ++k) a[size_t(k)] -= b[size_t(k)];
    return a;
}

BusyParts scaledTo(const BusyParts& p, Picos target, int fallback) {
    BusyParts out{};
    const Picos sum = sumOf(p);
    if (sum == 0) {
        out[size_t(fallback)] = target;
        return out;
    }
    if (sum == target) return p;
    // Floors of p * target / sum (128-bit: both can be near 2^63), then the
    // picoseconds left to the largest remainders.
    std::array<unsigned __int128, kBusyKinds> rem{};
    Picos given = 0;
    for (int k = 0; k < kBusyKinds; ++k) {
        const unsigned __int128 x = (unsigned __int128)p[size_t(k)] * target;
        out[size_t(k)] = Picos(x / sum);
        rem[size_t(k)] = x % sum;
        given += out[size_t(k)];
    }
    std::array<int, kBusyKinds> order;
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return rem[size_t(a)] > rem[size_t(b)]; });
    for (int i = 0; given < target; ++i, ++given) ++out[size_t(order[size_t(i)])];
    return out;
}

void trim(BusyParts& total, const BusyParts& last, Picos amount) {
    const Picos fromLast = std::min(amount, std::min(sumOf(last), sumOf(total)));
    BusyParts cut = scaledTo(last, fromLast);
    for (int k = 0; k < kBusyKinds; ++k) cut[size_t(k)] = std::min(cut[size_t(k)], total[size_t(k)]);
    total -= cut;
    const Picos rest = std::min(amount - sumOf(cut), sumOf(total));
    if (rest > 0) total -= scaledTo(total, rest);
}

}  // namespace rt
