#include "frame_state_json.h"

#include <set>
#include <stdexcept>
#include <string>

namespace rt {
namespace {

double number(const nlohmann::json& j, const char* key) { return j.contains(key) ? j.at(key).get<double>() : 0.0; }

Binned binned(const nlohmann::json& j, const char* values) {
    return {j.at("first_bin").get<int64_t>(), j.at(values).get<std::vector<double>>()};
}

WorkAlongAxis workAlongAxis(const nlohmann::json& p) {
    WorkAlongAxis w;
    w.axisFrom = p.at("axis_from").get<double>();
    w.binWidth = p.at("bin_width").get<double>();
    w.ns = binned(p, "ns");
    if (p.contains("within")) w.within = binned(p.at("within"), "ns");
    w.faceHandlingNs = number(p, "face_handling_ns");
    w.faceCrossings = p.value("face_crossings", uint64_t(0));
    if (p.contains("cuts_up")) w.cuts[0] = binned(p.at("cuts_up"), "rays");
    if (p.contains("cuts_down")) w.cuts[1] = binned(p.at("cuts_down"), "rays");
    if (p.contains("lateral"))
        for (const auto& [name, h] : p.at("lateral").items()) {
            // (named by linkSuffix: "px", "mx", ...)
            const std::optional<int> d = name.size() == 2 && (name[0] == 'p' || name[0] == 'm')
                                             ? dirNamed(std::string(name[0] == 'p' ? "+" : "-") + name[1])
                                             : std::nullopt;
            if (!d) throw std::runtime_error("not an rtsim report (a lateral direction '" + name + "')");
            w.lateral[size_t(*d)] = binned(h, "rays");
        }
    return w;
}

NodeFrameState nodeState(const nlohmann::json& node) {
    NodeFrameState n;
    n.cell = node.at("node").get<Cell>();
    const auto box = node.at("box").get<std::array<std::array<double, 3>, 2>>();
    n.box = Box{Vec3(box[0][0], box[0][1], box[0][2]), Vec3(box[1][0], box[1][1], box[1][2])};
    n.objects = node.value("objects", size_t(0));  // (none recorded: none moved)
    n.objectBytes = node.value("object_bytes", 0.0);
    if (node.contains("grid")) {
        n.gridCells = node.at("grid").at("cells").get<std::array<int, 3>>();
        const auto span = node.at("grid").at("span").get<std::array<std::array<double, 3>, 2>>();
        n.gridSpan = Box{Vec3(span[0][0], span[0][1], span[0][2]), Vec3(span[1][0], span[1][1], span[1][2])};
    }
    n.busyNs = node.at("busy_ns").get<double>();
    if (node.contains("work_by_position")) n.work = workAlongAxis(node.at("work_by_position"));
    return n;
}

FrameState read(const nlohmann::json& r) {
    FrameState f;
    f.dims = r.at("config").at("mesh").get<std::array<int, 3>>();
    const std::string axis = r.at("config").at("balance").at("axis").get<std::string>();
    f.axis = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
    if (f.axis < 0) throw std::runtime_error("not an rtsim report (config.balance.axis '" + axis + "')");
    f.renderTimeNs = r.value("render_time_ns", 0.0);
    std::set<std::pair<std::array<int, 2>, int>> seen;  // (a boundary twice: the later one won, silently)
    for (const auto& h : r.at("boundaries")) {
        BoundaryState b{h.at("column").get<std::array<int, 2>>(), h.at("index").get<int>(), {}};
        if (!seen.insert({b.column, b.index}).second)
            throw std::runtime_error("boundaries: column " + std::to_string(b.column[0]) + "," + std::to_string(b.column[1]) +
                                     "'s boundary " + std::to_string(b.index) + " given twice");
        for (const auto& p : h.at("history")) b.history.push_back({p.at(0).get<double>(), p.at(1).get<double>()});
        f.boundaries.push_back(std::move(b));
    }
    if (r.contains("nodes"))
        for (const auto& node : r.at("nodes")) f.nodes.push_back(nodeState(node));
    const nlohmann::json none = nlohmann::json::object();
    const nlohmann::json& totals = r.contains("totals") ? r.at("totals") : none;
    f.raysPassed = totals.value("rays_passed", uint64_t(0));
    const bool summed = totals.contains("ray_wire_ns");
    f.rayWireNs = summed ? totals.at("ray_wire_ns").get<double>() : 0;
    if (r.contains("links"))
        for (const auto& l : r.at("links"))
            if (l.value("to", "") != "fb") {
                if (!summed && l.contains("wire_ns")) f.rayWireNs += number(l.at("wire_ns"), "ray");
                f.busiestLinkWireNs = std::max(f.busiestLinkWireNs, number(l, "wire_busy_ns"));
            }
    return f;
}

}  // namespace

FrameState frameStateFromReport(const nlohmann::json& r) {
    try {
        return read(r);
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(std::string("not an rtsim report (") + e.what() + ")");
    }
}

}  // namespace rt
