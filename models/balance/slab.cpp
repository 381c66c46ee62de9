#include "balance/slab.h"

#include <unordered_set>

#include "channel/message.h"
#include "region.h"

namespace rt {

ObjectSplit splitObjects(const std::vector<Shape>& objects, const Box& slab, const Box& kept, double margin) {
    ObjectSplit s;
    for (const Shape& o : objects) {
        if (overlapsBox(o, slab, margin)) s.give.push_back(o);
        if (overlapsBox(o, kept, margin)) s.keep.push_back(o);
    }
    return s;
}

std::vector<Shape> uniteObjects(std::vector<Shape> own, std::vector<Shape> arriving) {
    std::unordered_set<uint32_t> have;
    for (const Shape& s : own) have.insert(s.id);
    for (Shape& s : arriving)
        if (have.insert(s.id).second) own.push_back(std::move(s));
    return own;
}

SlabLoad slabLoad(const std::vector<Shape>& objects, const Box& slab, double margin) {
    SlabLoad l;
    l.bytes = kHeaderBytes + kSlideBytes;
    for (const Shape& s : objects)
        if (overlapsBox(s, slab, margin)) {
            ++l.objects;
            l.bytes += objectBytes(s);
        }
    return l;
}

}  // namespace rt
