// The mesh's geometry: a node's six link directions, and the columns of
// nodes along the progress axis that the balancing works in
// (doc/balancing.md, "The progress axis and the columns").
#pragma once
#include <array>
#include <optional>
#include <string>

#include "lattice.h"

namespace rt {

// Link directions of a node, in port order.
enum Dir : int { PosX = 0, NegX = 1, PosY = 2, NegY = 3, PosZ = 4, NegZ = 5 };
constexpr int kDirs = 6;
inline int dirAxis(int d) { return d / 2; }
inline int dirStep(int d) { return (d % 2) ? -1 : 1; }
inline int opposite(int d) { return d ^ 1; }
inline int dirOf(int axis, int step) { return 2 * axis + (step < 0 ? 1 : 0); }
inline const char* dirName(int d) {  // "+x", "-x", ...
    static const char* names[kDirs] = {"+x", "-x", "+y", "-y", "+z", "-z"};
    return names[d];
}
// The direction named "+x" .. "-z", if `name` is one.
inline std::optional<int> dirNamed(const std::string& name) {
    for (int d = 0; d < kDirs; ++d)
        if (name == dirName(d)) return d;
    return std::nullopt;
}

// Whether `c` is a node of a mesh of `dims`.
inline bool inMesh(const Cell& c, const std::array<int, 3>& dims) {
    for (int a = 0; a < 3; ++a)
        if (c[a] < 0 || c[a] >= dims[a]) return false;
    return true;
}
// The node next to `c` in direction `d` (it may be outside the mesh).
inline Cell neighbour(Cell c, int d) {
    c[dirAxis(d)] += dirStep(d);
    return c;
}

// Nodes are numbered x fastest, then y, then z.
inline size_t nodeIndex(const Cell& c, const std::array<int, 3>& dims) {
    return (size_t(c[2]) * size_t(dims[1]) + size_t(c[1])) * size_t(dims[0]) + size_t(c[0]);
}
inline Cell cellAt(size_t i, const std::array<int, 3>& dims) {
    return {int(i % size_t(dims[0])), int(i / size_t(dims[0]) % size_t(dims[1])), int(i / size_t(dims[0]) / size_t(dims[1]))};
}
// Names in the report and the VCD: node_X_Y_Z, and its links' suffixes
// ("px", "mz", ...).
inline std::string nodeName(const Cell& c) {
    return "node_" + std::to_string(c[0]) + "_" + std::to_string(c[1]) + "_" + std::to_string(c[2]);
}
// A node as the flags name it: "x,y,z".
inline std::string cellText(const Cell& c) { return std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]); }
inline std::string linkSuffix(int d) { return std::string(d % 2 ? "m" : "p") + "xyz"[dirAxis(d)]; }

// The columns along the progress axis: the nodes that share their
// coordinates on the other two axes, u = axis + 1 and v = axis + 2 (mod 3).
// A column is named by those two coordinates (i, j) and numbered i + U j
// (U nodes along u); its nodes by their place k along the axis.
struct ColumnGeometry {
    int axis, u, v;
    std::array<int, 3> dims;
    ColumnGeometry(int axis_, const std::array<int, 3>& dims_)
        : axis(axis_), u((axis_ + 1) % 3), v((axis_ + 2) % 3), dims(dims_) {}
    int length() const { return dims[axis]; }    // nodes along a column
    int count() const { return dims[u] * dims[v]; }  // columns
    int indexOf(int i, int j) const { return i + dims[u] * j; }
    int columnOf(const Cell& c) const { return indexOf(c[u], c[v]); }
    // Node k of column (i, j).
    Cell cell(int i, int j, int k) const {
        Cell c{};
        c[u] = i;
        c[v] = j;
        c[axis] = k;
        return c;
    }
    // Whether (i, j) names a column of the mesh.
    bool isColumn(int i, int j) const { return i >= 0 && i < dims[u] && j >= 0 && j < dims[v]; }
};

}  // namespace rt
