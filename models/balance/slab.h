// Slab exchange, the paper's sliding boundary (section 2): the giver's box
// loses the slab between one of its faces along the progress axis and the
// new boundary, the taker's box gains it, and the objects that overlap the
// slab travel with it. The geometry and the object sets, for both ends;
// the protocol that decides a slide is balance_agent.h, the node's side of
// it node_balance.cpp. Plain C++ (sw/ types).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "box.h"
#include "shape.h"

namespace rt {

// `b` with its face on `side` (-1 lower, +1 upper) along `axis` moved to `at`.
inline Box withFace(Box b, int axis, int side, double at) {
    if (side > 0) b.hi[axis] = at;
    else b.lo[axis] = at;
    return b;
}

// The slab of `b` between its face on `side` and `at`: what the giver hands over.
inline Box slabOf(const Box& b, int axis, int side, double at) { return withFace(b, axis, -side, at); }

// The giver's objects, split: those that overlap the slab (they go with it)
// and those that overlap the box it keeps (an object may be in both).
struct ObjectSplit {
    std::vector<Shape> give, keep;
};
ObjectSplit splitObjects(const std::vector<Shape>& objects, const Box& slab, const Box& kept, double margin);

// The taker's objects: its own and the slab's, each once (by id).
std::vector<Shape> uniteObjects(std::vector<Shape> own, std::vector<Shape> arriving);

// What a slab would carry, for the guard's estimate of its cost: the
// objects that overlap it, and the bytes of the slide message with them.
struct SlabLoad {
    size_t objects = 0;
    uint32_t bytes = 0;
};
SlabLoad slabLoad(const std::vector<Shape>& objects, const Box& slab, double margin);

}  // namespace rt
