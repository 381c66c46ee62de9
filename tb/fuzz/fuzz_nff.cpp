// libFuzzer target for the scene reader (scripts/fuzz.sh): any text must
// either give a scene or a SceneError ("file:line: what"), never a crash, a
// hang, another exception or undefined behaviour (the build adds
// AddressSanitizer and UndefinedBehaviorSanitizer). A scene it accepts is
// also rendered at 4x4 with the grid, if small, so what the reader lets
// through is exercised by the geometry too.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nff_reader.h"
#include "partition.h"
#include "renderer.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rt::Scene scene;
    try {
        scene = rt::parseNff(std::string(reinterpret_cast<const char*>(data), size), "fuzz.nff");
    } catch (const rt::SceneError&) {
        return 0;  // bad input, said so: what the reader must do
    }
    if (scene.objects.size() > 200) return 0;  // keep an execution short
    rt::RenderOptions o;
    o.width = o.height = 4;
    o.maxDepth = 1;
    rt::render(scene, rt::Partition::whole(scene), o);
    return 0;
}
