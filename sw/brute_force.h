// Every object against every ray: the yardstick the grid is tested against.
#pragma once
#include "accelerator.h"

namespace rt {

class BruteForce final : public Accelerator {
public:
    explicit BruteForce(const std::vector<Shape>& objects) : objects_(objects) {}
    Hit closestHit(const Ray& r, double t0, double t1, Mailbox&, Counters& counters) const override {
        Hit best;
        for (uint32_t i = 0; i < objects_.size(); ++i) testObject(objects_, i, r, t0, t1, best, counters);
        return best;
    }
    std::string describe() const override { return "brute force"; }

private:
    const std::vector<Shape>& objects_;
};

}  // namespace rt
