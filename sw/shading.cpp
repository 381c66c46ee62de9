#include "shading.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "camera.h"
#include "lattice.h"

namespace rt {

const char* rayKindName(RayKind k) {
    switch (k) {
        case RayKind::Primary: return "primary";
        case RayKind::Shadow: return "shadow";
        case RayKind::Reflected: return "reflected";
        case RayKind::Refracted: return "refracted";
    }
    return "?";
}

Shader::Shader(const Scene& scene, int maxDepth)
    : background_(scene.background),
      lights_(scene.lights),
      materials_(scene.materials),
      maxDepth_(maxDepth),
      eps_(scene.rayEpsilon()) {
    const double n = double(std::max<size_t>(lights_.size(), 1));
    intensity_ = std::sqrt(n) / (2.0 * n);
}

static void countHit(RayKind kind, Counters& c) {
    if (kind == RayKind::Primary) ++c.primaryHits;
    else if (kind == RayKind::Shadow) ++c.shadowHits;
    else ++c.secondaryHits;
}

void Shader::spawn(std::vector<RayJob>& spawned, const RayJob& parent, const Vec3& origin, const Vec3& dir,
                   const Vec3& weight, RayKind kind, uint64_t childDigit, Counters& counters) const {
    RayJob j;
    j.ray = Ray(origin, dir);
    j.t0 = eps_;
    j.tEnd = std::numeric_limits<double>::infinity();
    j.weight = weight;
    j.pixel = parent.pixel;
    j.key = PathKey{parent.key.path * 3 + childDigit, 0};
    j.depth = uint8_t(parent.depth + 1);
    j.kind = kind;
    ++counters.secondaryRays;
    spawned.push_back(j);
}

void Shader::hit(const RayJob& job, double t, const Shape& object, Counters& counters, std::vector<RayJob>& spawned,
                 std::vector<Contribution>& out) const {
    countHit(job.kind, counters);
    if (job.kind == RayKind::Shadow) return;  // blocked: the light does not reach the point
    ++counters.shadings;
    const Material& m = materials_[object.material];
    const Vec3& d = job.ray.d;
    const Vec3 p = job.ray.at(t);
    Vec3 n = object.normal(p);            // the visible side
    const bool entering = glm::dot(n, d) < 0;
    if (!entering) n = -n;                // two-sided (transparent) hit from behind: face the ray
    const Vec3 surface = job.weight * m.colour;

    // Ambient.
    out.push_back(Contribution{job.pixel, PathKey{job.key.path, 0}, surface * (m.kd * intensity_)});
    ++counters.contributions;

    // Direct light: one shadow ray per light on the visible side.
    const Vec3 mirrorDir = d - 2.0 * glm::dot(d, n) * n;
    for (size_t i = 0; i < lights_.size(); ++i) {
        const Vec3 toLight = lights_[i].position - p;
        const double dist = glm::length(toLight);
        if (!(dist > eps_)) continue;
        const Vec3 l = toLight / dist;
        const double ndl = glm::dot(n, l);
        if (!(ndl > 0)) continue;
        const double rl = glm::dot(mirrorDir, l);
        const double highlight = (m.ks > 0 && rl > 0) ? m.ks * std::pow(rl, m.shine) : 0.0;
        const Vec3 add = job.weight * lights_[i].colour * intensity_ * (m.kd * ndl * m.colour + Vec3(highlight));
        if (add == Vec3(0.0)) continue;
        RayJob s;
        s.ray = Ray(p, l);
        s.t0 = eps_;
        s.tEnd = dist;
        s.weight = add;
        s.pixel = job.pixel;
        s.key = PathKey{job.key.path, uint32_t(1 + i)};
        s.depth = job.depth;
        s.kind = RayKind::Shadow;
        ++counters.shadowRays;
        spawned.push_back(s);
    }

    if (job.depth >= maxDepth_) return;
    if (m.ks > 0) spawn(spawned, job, p, mirrorDir, job.weight * m.ks, RayKind::Reflected, 1, counters);
    if (m.t > 0) {
        const double eta = entering ? 1.0 / m.ior : m.ior;
        const double cosi = -glm::dot(d, n);
        const double k = 1.0 - eta * eta * (1.0 - cosi * cosi);
        // Total internal reflection sends the transmitted weight along the mirror direction.
        const Vec3 dir = k < 0 ? mirrorDir : glm::normalize(eta * d + (eta * cosi - std::sqrt(k)) * n);
        spawn(spawned, job, p, dir, job.weight * m.t, RayKind::Refracted, 2, counters);
    }
}

Contribution Shader::miss(const RayJob& job, Counters& counters) const {
    ++counters.contributions;
    if (job.kind == RayKind::Shadow) return Contribution{job.pixel, job.key, job.weight};
    return Contribution{job.pixel, PathKey{job.key.path, 0}, job.weight * background_};
}

RayJob primaryJob(const Camera& camera, int x, int y, const Box& world) {
    RayJob j;
    j.ray = camera.primaryRay(x, y);
    j.t0 = std::max(0.0, boxInterval(j.ray, world).lo);
    j.tEnd = std::numeric_limits<double>::infinity();
    j.pixel = uint32_t(y) * uint32_t(camera.width()) + uint32_t(x);
    j.kind = RayKind::Primary;
    return j;
}

}  // namespace rt
