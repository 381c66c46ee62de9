// Whitted shading, forward: a hit emits its ambient term, spawns one shadow
// ray per light carrying the diffuse + highlight it would add, a mirror ray
// carrying its weight times Ks, and a refracted ray carrying weight times T.
// A shadow ray that reaches its light delivers its contribution; one that is
// blocked delivers nothing. A ray that leaves the world delivers the
// background times its weight. The model is written down in doc/rendering.md.
#pragma once
#include <vector>

#include "counters.h"
#include "ray_job.h"
#include "scene.h"

namespace rt {

class Shader {
public:
    Shader(const Scene& scene, int maxDepth);

    // Intensity of each light and of the ambient term: sqrt(L) / (2 L) for L
    // lights (SPD's suggestion).
    double lightIntensity() const { return intensity_; }
    double rayEpsilon() const { return eps_; }

    // The ray hit `object` at t (the hit is counted here).
    void hit(const RayJob& job, double t, const Shape& object, Counters& counters, std::vector<RayJob>& spawned,
             std::vector<Contribution>& out) const;
    // The ray ended without a hit: it left the world, or it is a shadow ray
    // that reached its light.
    Contribution miss(const RayJob& job, Counters& counters) const;

private:
    void spawn(std::vector<RayJob>& spawned, const RayJob& parent, const Vec3& origin, const Vec3& dir,
               const Vec3& weight, RayKind kind, uint64_t childDigit, Counters& counters) const;

    Vec3 background_;
    std::vector<Light> lights_;
    std::vector<Material> materials_;
    int maxDepth_;
    double intensity_;
    double eps_;
};

// Creates the primary ray job of pixel (x, y), starting where the ray enters
// the world box (or at the eye when the eye is inside it).
class Camera;
RayJob primaryJob(const Camera& camera, int x, int y, const Box& world);

}  // namespace rt
