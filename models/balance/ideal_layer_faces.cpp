#include "balance/ideal_layer_faces.h"

#include <algorithm>
#include <stdexcept>

namespace rt {

IdealLayerFaces::IdealLayerFaces(std::vector<double> faces, double lo, double hi, double deadband, double gain,
                                 double minThickness)
    : lo_(lo), hi_(hi), deadband_(deadband), gain_(gain), minThickness_(minThickness) {
    planes_.push_back(std::move(faces));
}

void IdealLayerFaces::add(int layer, long interval, Picos exec, Picos wait) {
    auto& s = sums_[{layer, interval}];
    s.first += double(exec);
    s.second += double(wait);
}

double IdealLayerFaces::load(int layer, long interval) const {
    const auto it = sums_.find({layer, interval});
    if (it == sums_.end()) return 0;
    const double exec = it->second.first, all = it->second.first + it->second.second;
    return all > 0 ? exec / all : 0;
}

// The paper's rule (policy_slide.cpp) with layers for nodes, one face after
// the other from the lowest, each judged on the planes as the faces before
// it left them (as a node giving on both sides counts its first slide).
double IdealLayerFaces::face(int k, long through) {
    const std::vector<double>& first = planes_.front();
    if (k < 0 || size_t(k) >= first.size() || through < 0)
        throw std::logic_error("ideal layer faces: no plane " + std::to_string(k) + " after " + std::to_string(through));
    while (long(planes_.size()) <= through) {
        const long t = long(planes_.size()) - 1;
        std::vector<double> f = planes_.back();
        const int faces = int(f.size());
        for (int i = 0; i < faces; ++i) {
            const double below = i ? f[size_t(i - 1)] : lo_, above = i + 1 < faces ? f[size_t(i + 1)] : hi_;
            const double diff = load(i, t) - load(i + 1, t);
            double& p = f[size_t(i)];
            if (diff > deadband_)  // layer i is heavier: the face moves into it
                p = std::max(std::min(p, below + minThickness_), p - gain_ * diff * (p - below));
            else if (-diff > deadband_)
                p = std::min(std::max(p, above - minThickness_), p + gain_ * -diff * (above - p));
        }
        planes_.push_back(std::move(f));
    }
    return planes_[size_t(through)][size_t(k)];
}

}  // namespace rt
