// rtref: the sequential reference renderer.
//   rtref [SCENE.nff] -o OUT.png [--size WxH] [--stats OUT.json] [--max-depth D] [--threads T]
// Without a scene file it renders the built-in procedural scene.
#include <chrono>
#include <fstream>
#include <iostream>
#include <optional>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "counters.h"
#include "counters_json.h"
#include "grid.h"
#include "memory_estimate.h"
#include "output_file.h"
#include "renderer.h"
#include "scene_error.h"
#include "scene_options.h"

namespace {

nlohmann::json statsJson(const rt::Scene& scene, const rt::RenderResult& r, int depth, int threads, double wall,
                         const std::string& accel) {
    const rt::Counters& c = r.counters;
    nlohmann::json j;
    j["scene"] = scene.name;
    j["width"] = r.image.width;
    j["height"] = r.image.height;
    j["objects"] = scene.objects.size();
    j["lights"] = scene.lights.size();
    j["max_depth"] = depth;
    j["threads"] = threads;
    j["accelerator"] = accel;
    j.update(rt::countersJson(c));
    j["wall_s"] = wall;
    j["rays_per_s"] = wall > 0 ? double(c.rays()) / wall : 0.0;
    return j;
}

// The outputs first: a path that cannot be written is found now, not after
// the render.
void checkOutputs(const std::string& out, const std::string& stats, const rt::SceneOptions& sceneOpt) {
    rt::checkWritable("--output", out);
    rt::checkExtension("--output", out, {".png"});
    std::vector<rt::NamedFile> files{{"--output", out, true}};
    if (!stats.empty()) {
        rt::checkWritable("--stats", stats);
        rt::checkExtension("--stats", stats, {".json"});
        files.push_back({"--stats", stats, true});
    }
    if (!sceneOpt.file.empty()) files.push_back({"the scene", sceneOpt.file, false});
    rt::checkDistinct(files);  // (no output over another, or over the scene)
}

// Objects that overlap many cells make the grid's references grow as their
// count squared: refused with the estimate, not a bad_alloc.
void checkFits(const rt::Scene& scene, const rt::RenderOptions& ro, const rt::SceneOptions& sceneOpt) {
    rt::refuseIfTooBig(sceneOpt.sizeNamed(ro.width, ro.height),
                       rt::kRtrefBytesPerPixel * ro.width * ro.height);
    const rt::UniformGrid::Size grid = rt::UniformGrid::sizeFor(scene.objects, scene.worldBox());
    if (grid.references > rt::UniformGrid::kMaxReferences)
        throw rt::SceneError(scene.name + ": a grid of " + std::to_string(grid.references) +
                             " references (objects listed in cells), more than a grid holds (2^32 - 1)");
    rt::refuseIfTooBig(scene.name + ": its " + std::to_string(scene.objects.size()) + " objects binned into its grid",
                       grid.bytes(scene.objects.size()) + rt::kRtrefBytesPerPixel * ro.width * ro.height);
}

void printSummary(const rt::Scene& scene, const rt::RenderResult& r, const std::string& accel, const std::string& out,
                  double wall) {
    const rt::Counters& c = r.counters;
    std::cout << "rtref: " << scene.name << " (" << scene.objects.size() << " objects, " << accel << ") "
              << r.image.width << "x" << r.image.height << " -> " << out << "\n"
              << "  rays: " << c.primaryRays << " primary (" << c.primaryHits << " hit), " << c.shadowRays
              << " shadow (" << c.shadowHits << " blocked), " << c.secondaryRays << " secondary ("
              << c.secondaryHits << " hit)\n"
              << "  intersection tests: " << c.intersectionTests() << ", voxel steps: " << c.voxelSteps << "\n"
              << "  wall: " << wall << " s, " << (wall > 0 ? double(c.rays()) / wall : 0.0) << " rays/s\n";
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"rtref: sequential reference ray tracer (NFF scenes or the built-in procedural scene)"};
    rt::SceneOptions sceneOpt;
    sceneOpt.procedural.concentration = rt::kDefaultConcentration;  // (rtsim's built-in scene)
    std::string out = "rtref.png", stats;
    int depth = 5, threads = 1;
    sceneOpt.addTo(app, true);
    app.add_option("-o,--output", out, "output PNG file")->capture_default_str();
    app.add_option("--stats", stats, "write counters and wall time as JSON");
    app.add_option("--max-depth", depth, "mirror/refraction levels below the primary ray")
        ->check(CLI::Range(0, rt::kMaxRayDepth))
        ->capture_default_str();
    app.add_option("--threads", threads, "rendering threads (the image does not depend on it)")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    rt::decimalNumbersOnly(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "rtref: error: " << e.what() << "\n";
        return 2;
    }
    try {
        checkOutputs(out, stats, sceneOpt);
        const rt::Scene scene = sceneOpt.load();
        rt::RenderOptions ro;
        sceneOpt.imageSize(scene, ro.width, ro.height);
        checkFits(scene, ro, sceneOpt);
        ro.maxDepth = depth;
        ro.threads = threads;
        const auto t0 = std::chrono::steady_clock::now();
        const rt::Partition whole = rt::Partition::whole(scene);
        const rt::RenderResult r = rt::render(scene, whole, ro);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        // Written whole or not at all (output_file.h): the image and the
        // stats to temporary files, renamed once both are written.
        rt::AtomicFile image(out);
        rt::writePng(r.image, image.temp());
        const std::string accel = whole.region(size_t(0)).accelerator().describe();
        std::optional<rt::AtomicFile> statsFile;
        if (!stats.empty()) {
            statsFile.emplace(stats);
            statsFile->write(statsJson(scene, r, depth, threads, wall, accel).dump(2) + "\n");
        }
        image.commit();
        if (statsFile) statsFile->commit();
        printSummary(scene, r, accel, out, wall);
    } catch (const rt::SceneError& e) {
        std::cerr << "rtref: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "rtref: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
