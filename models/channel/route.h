// Where a ray is forwarded. A node owns the part of a ray's parameter line
// inside its box (one half-open rule: sw/lattice.h); a ray that reaches it
// at a parameter it does not own goes on towards the owner. Plain C++.
#pragma once
#include "lattice.h"
#include "base/mesh_geometry.h"
#include "ray_job.h"

namespace rt {

// The link direction towards the owner of job.t0 from the node whose box
// is `box` (`slabs`: boxSlabs(job.ray, box)), or -1 if that node owns it.
// The first axis whose slab does not own t0 picks the direction; a
// neighbour that does not own it either forwards it on, so a ray always
// reaches its owner, also when the columns' boundaries along the progress
// axis do not line up.
inline int routeRay(const RayJob& job, const BoxSlabs& slabs, const Box& box) {
    // Owned when every slab holds t0: when their intersection does (the usual case).
    if (slabs.span.lo <= job.t0 && job.t0 < slabs.span.hi) return -1;
    for (int a = 0; a < 3; ++a) {
        if (job.ray.d[a] == 0) {
            const double o = job.ray.o[a];
            if (o < box.lo[a]) return dirOf(a, -1);
            if (o >= box.hi[a]) return dirOf(a, +1);
            continue;
        }
        const Interval s = slabs.slab[size_t(a)];
        const int forward = job.ray.d[a] > 0 ? +1 : -1;  // moving along the ray moves this way on axis a
        if (job.t0 < s.lo) return dirOf(a, -forward);
        if (job.t0 >= s.hi) return dirOf(a, forward);
    }
    return -1;
}

}  // namespace rt
