// NFF reader: the SPD files parse with the counts their README lists, and
// each kind of bad input gives a one-line "file:line: ..." error.
#include <filesystem>
#include <fstream>
#include <random>
#include <utility>

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "nff_reader.h"
#include "partition.h"

using namespace rt;

namespace {

struct SpdCounts {
    const char* file;
    int s, c, p, l, f;
};

int countKind(const Scene& s, PrimitiveKind k) {
    int n = 0;
    for (const Shape& o : s.objects) n += o.kind() == k;
    return n;
}

// The table in shared/scenes/spd/README.md (pp is 0 everywhere).
const SpdCounts kSpd[] = {
    {"balls-1", 10, 0, 1, 3, 2},     {"balls-2", 91, 0, 1, 3, 2},   {"balls-3", 820, 0, 1, 3, 2},
    {"balls-4", 7381, 0, 1, 3, 2},   {"balls-5", 66430, 0, 1, 3, 2}, {"rings-2", 150, 150, 1, 3, 31},
    {"tetra-3", 0, 0, 64, 1, 1},     {"gears-2", 0, 0, 1169, 5, 9},
};

const char* kHeader =
    "b 0.1 0.2 0.3\n"
    "v\n"
    "from 0 -5 0\n"
    "at 0 0 0\n"
    "up 0 0 1\n"
    "angle 45\n"
    "hither 0.01\n"
    "resolution 64 48\n"
    "l 1 2 3\n"
    "f 1 0 0 0.5 0.5 3 0 1\n";  // 10 lines

// Parses kHeader + tail and returns the error message ("" if none).
std::string errorOf(const std::string& text) {
    try {
        parseNff(text, "bad.nff");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(Nff, SpdScenesHaveTheirPrimitiveCounts) {
    for (const SpdCounts& e : kSpd) {
        SCOPED_TRACE(e.file);
        const Scene s = readNff(std::string(RT_SCENE_DIR) + "/" + e.file + ".nff");
        EXPECT_EQ(countKind(s, PrimitiveKind::Sphere), e.s);
        EXPECT_EQ(countKind(s, PrimitiveKind::Cone), e.c);
        EXPECT_EQ(countKind(s, PrimitiveKind::Polygon), e.p);
        EXPECT_EQ(int(s.lights.size()), e.l);
        EXPECT_EQ(int(s.materials.size()), e.f);
        EXPECT_EQ(s.view.width, 512);
        EXPECT_EQ(s.view.height, 512);
        EXPECT_DOUBLE_EQ(s.view.angle, 45);
        for (size_t i = 0; i < s.objects.size(); ++i) ASSERT_EQ(s.objects[i].id, i);
    }
}

TEST(Nff, ReadsViewBackgroundLightsAndMaterial) {
    const Scene s = parseNff(std::string(kHeader) + "l 4 5 6 0.5 0.25 1\ns 1 2 3 0.5\n", "ok.nff");
    EXPECT_EQ(s.view.from, Vec3(0, -5, 0));
    EXPECT_EQ(s.view.up, Vec3(0, 0, 1));
    EXPECT_EQ(s.view.width, 64);
    EXPECT_EQ(s.view.height, 48);
    EXPECT_EQ(s.background, Vec3(0.1, 0.2, 0.3));
    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].colour, Vec3(1.0));  // no colour given: white
    EXPECT_EQ(s.lights[1].colour, Vec3(0.5, 0.25, 1));
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].colour, Vec3(1, 0, 0));
    EXPECT_DOUBLE_EQ(s.materials[0].kd, 0.5);
    EXPECT_DOUBLE_EQ(s.materials[0].shine, 3);
    ASSERT_EQ(s.objects.size(), 1u);
    EXPECT_FALSE(s.objects[0].twoSided);
}

TEST(Nff, LightColourIsOnlyReadFromTheSameLine) {
    // A number on the next line is not the light's colour: it is an error
    // (no keyword), so the reader must not swallow it silently.
    EXPECT_NE(errorOf(std::string(kHeader) + "l 4 5 6\n0.5 0.5 0.5\n"), "");
}

TEST(Nff, ConeBothLayoutsAgree) {
    const Scene a = parseNff(std::string(kHeader) + "c 0 0 0 1 0 0 2 0.5\n", "a.nff");
    const Scene b = parseNff(std::string(kHeader) + "c\n0 0 0 1\n0 0 2 0.5\n", "b.nff");
    const Cone& ca = std::get<Cone>(a.objects.at(0).geometry);
    const Cone& cb = std::get<Cone>(b.objects.at(0).geometry);
    EXPECT_EQ(ca.base, cb.base);
    EXPECT_EQ(ca.apex, cb.apex);
    EXPECT_EQ(ca.baseRadius, 1.0);
    EXPECT_EQ(cb.apexRadius, 0.5);
}

TEST(Nff, CommentsAndPolygonWithNormals) {
    const Scene s = parseNff(std::string("# a comment\n") + kHeader +
                                 "pp 3 # triangle with normals\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n"
                                 "# s 0 0 0 1\n",
                             "c.nff");
    ASSERT_EQ(s.objects.size(), 1u);
    EXPECT_EQ(s.objects[0].kind(), PrimitiveKind::Polygon);
    EXPECT_EQ(std::get<Polygon>(s.objects[0].geometry).n, Vec3(0, 0, 1));
}

TEST(Nff, TransparentMaterialMakesObjectsTwoSided) {
    const Scene s = parseNff(std::string(kHeader) + "f 1 1 1 0.2 0.1 10 0.8 1.5\ns 0 0 0 1\n", "t.nff");
    EXPECT_TRUE(s.objects.at(0).twoSided);
    EXPECT_DOUBLE_EQ(s.materials.at(1).ior, 1.5);
}

TEST(Nff, NegativeRadiiMeanInsideVisible) {
    const Scene s = parseNff(std::string(kHeader) + "s 0 0 0 -2\nc 0 0 0 -1 0 0 1 -1\n", "n.nff");
    EXPECT_TRUE(std::get<Sphere>(s.objects.at(0).geometry).insideVisible);
    EXPECT_DOUBLE_EQ(std::get<Sphere>(s.objects.at(0).geometry).radius, 2);
    EXPECT_TRUE(std::get<Cone>(s.objects.at(1).geometry).insideVisible);
}

// A scene flat along an axis far from the origin (a polygon in the plane
// x = 1e9) still has a world box whose planes are apart: its padding grows
// with the distance from the origin (the planes once collapsed, exit 1).
TEST(Nff, AFlatSceneFarFromTheOriginStillSplitsIntoBoxes) {
    const Scene s = parseNff(std::string(kHeader) + "p 3\n1e9 0 0\n1e9 1e-9 0\n1e9 0 1e-9\n", "far.nff");
    const Box w = s.worldBox();
    EXPECT_LT(w.lo.x, 1e9);
    EXPECT_GT(w.hi.x, 1e9);
    EXPECT_NO_THROW(Partition::uniform(s, {16, 16, 16}));
}

struct BadCase {
    const char* name;
    std::string text;
    std::string expect;  // must appear in the message, after "bad.nff:LINE:"
};

class NffBadInput : public testing::TestWithParam<BadCase> {};

TEST_P(NffBadInput, GivesOneLineErrorWithFileAndLine) {
    const BadCase& c = GetParam();
    const std::string msg = errorOf(c.text);
    ASSERT_NE(msg, "") << "accepted bad input";
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
}

static std::string H(const std::string& tail) { return std::string(kHeader) + tail; }

INSTANTIATE_TEST_SUITE_P(
    All, NffBadInput,
    testing::Values(
        BadCase{"UnknownKeyword", H("sphere 0 0 0 1\n"), "bad.nff:11: unknown keyword 'sphere'"},
        BadCase{"MissingToken", H("s 0 0 0\n"), "bad.nff:11: expected sphere radius, got end of file"},
        // A binary file's bytes, a NUL among them, quoted as \xNN: raw, they
        // were not UTF-8 and broke the sweep driver's reading of the message,
        // and the NUL cut it short. (A token of one 'M' and 99 more bytes: 40 shown.)
        BadCase{"BinaryKeyword", H(std::string("M\xcc\xe4\0z", 5) + std::string(95, 'q') + "\n"),
                "bad.nff:11: unknown keyword 'M\\xcc\\xe4\\x00z" + std::string(35, 'q') + "...'"},
        BadCase{"BinaryNumber", H(std::string("s 0 0 0 \x01\n")), "got '\\x01'"},
        BadCase{"NonNumeric", H("s 0 0 zero 1\n"), "bad.nff:11: expected a number for sphere centre"},
        BadCase{"TrailingGarbageInNumber", H("s 0 0 0 1x\n"), "bad.nff:11: expected a number for sphere radius"},
        BadCase{"NaN", H("s 0 0 nan 1\n"), "bad.nff:11: expected a finite number"},
        BadCase{"Infinity", H("l inf 0 0\n"), "bad.nff:11: expected a finite number"},
        BadCase{"HugeRadius", H("s 0 0 0 2e9\n"), "bad.nff:11: expected a number of magnitude at most 1e9 for sphere radius"},
        // scripts/fuzz.sh's finding, as it found it: a centre at 1.1e98 made
        // the world box's grid planes collapse (an uncaught exception).
        BadCase{"FuzzHugeCentre",
                "b 0.078 0.361 0.753\nv\nfrom 2.1 1.3 1.7\nat 0 0 0\nup 0 0 1\nangle 22\nhither 0.01\n"
                "resolution 512 512\nl 4 3 2\nl 1 -0.544331 0.16666725667\ns 5.471405 -7045.041 1.11022e098 -1.4",
                "bad.nff:11: expected a number of magnitude at most 1e9 for sphere centre"},
        // A sphere with no extent at its centre (1e-9 at 1e9: the world
        // box's planes collapsed, exit 1 naming no file).
        BadCase{"SphereTooSmallForItsCentre", H("s 1e9 0 0 1e-9\n"),
                "bad.nff:11: sphere radius 1e-09 is too small for a centre that far from the origin (1e+09)"},
        BadCase{"PolygonTwoVertices", H("p 2\n0 0 0\n1 0 0\n"), "bad.nff:11: polygon needs at least 3 vertices"},
        BadCase{"PolygonCollinear", H("p 3\n0 0 0\n1 1 1\n2 2 2\n"), "bad.nff:11: polygon vertices are collinear"},
        BadCase{"PolygonShort", H("p 3\n0 0 0\n1 0 0\n"), "expected vertex 3 of 'p', got end of file"},
        BadCase{"PolygonCountNotInteger", H("p 3.5\n"), "bad.nff:11: expected an integer for vertex count"},
        BadCase{"ZeroResolution", "v\nfrom 0 0 -5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 0 64\n",
                "bad.nff:7: 'resolution' must be positive"},
        BadCase{"NegativeResolution", "v\nfrom 0 0 -5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 64 -1\n",
                "bad.nff:7: 'resolution' must be positive"},
        BadCase{"ZeroUp", "v\nfrom 0 0 -5\nat 0 0 0\nup 0 0 0\nangle 45\nhither 1\nresolution 8 8\n",
                "bad.nff:4: 'up' vector has zero length"},
        BadCase{"FromEqualsAt", "v\nfrom 1 2 3\nat 1 2 3\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n",
                "bad.nff:3: 'from' and 'at' are the same point"},
        BadCase{"UpAlongView", "v\nfrom 0 0 -5\nat 0 0 0\nup 0 0 2\nangle 45\nhither 1\nresolution 8 8\n",
                "bad.nff:4: 'up' is parallel to the viewing direction"},
        BadCase{"NoView", "s 0 0 0 1\n", "bad.nff:1: no viewpoint"},
        BadCase{"ViewIncomplete", "v\nfrom 0 0 -5\nat 0 0 0\n", "viewpoint block lacks 'up'"},
        BadCase{"BadAngle", "v\nfrom 0 0 -5\nat 0 0 0\nup 0 1 0\nangle 180\n", "bad.nff:5: 'angle' must be in (0, 180)"},
        BadCase{"ZeroRadius", H("s 0 0 0 0\n"), "bad.nff:11: sphere radius must not be zero"},
        BadCase{"DegenerateCone", H("c 0 0 0 1 0 0 0 1\n"), "bad.nff:11: degenerate cone"},
        BadCase{"ConeMixedSigns", H("c 0 0 0 1 0 0 1 -1\n"), "bad.nff:11: cone radii must not have opposite signs"},
        BadCase{"MaterialShort", H("f 1 1 1 0.5 0.5 3 0\n"), "expected index of refraction of 'f', got end of file"},
        BadCase{"BadTransmittance", H("f 1 1 1 0.5 0.5 3 2 1\n"), "bad.nff:11: transmittance T of 'f' must be in [0, 1]"},
        // (A negative Phong exponent made inf, and NaN against a light's zero channel: NaN pixels, exit 0.)
        BadCase{"NegativeShine", H("f 1 1 1 0.5 0.5 -1e9 0 1\n"), "bad.nff:11: Phong exponent Shine of 'f' must be at least 0"},
        BadCase{"NegativeKd", H("f 1 1 1 -0.5 0.5 3 0 1\n"), "bad.nff:11: diffuse Kd of 'f' must be at least 0"},
        BadCase{"NegativeKs", H("f 1 1 1 0.5 -0.5 3 0 1\n"), "bad.nff:11: specular Ks of 'f' must be at least 0"},
        BadCase{"NegativeColour", H("f -1 1 1 0.5 0.5 3 0 1\n"), "bad.nff:11: material colour 'f r g b' must not be below 0"},
        BadCase{"NegativeLight", H("l 1 1 1 1 -5 1\n"), "bad.nff:11: light colour 'l x y z r g b' must not be below 0"},
        BadCase{"NegativeBackground", H("b 0 0 -1\n"), "bad.nff:11: background colour 'b r g b' must not be below 0"}),
    [](const testing::TestParamInfo<BadCase>& i) { return std::string(i.param.name); });

TEST(Nff, MissingFileIsAnError) {
    try {
        readNff("/nonexistent/scene.nff");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.nff: no such scene file"), std::string::npos);
    }
}

// A folder or a FIFO is there but is no scene file (a FIFO would block the read): said so, not "no such scene file".
TEST(Nff, AFolderOrAFifoIsNoSceneFile) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("nff-fifo-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string fifo = (dir / "scene.nff").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    for (const auto& [path, says] : {std::pair<std::string, std::string>{dir.string(), ": a folder, not a scene file"},
                                     {fifo, ": not a regular file (a FIFO, device or socket)"}}) {
        try {
            readNff(path);
            ADD_FAILURE() << path << ": no error";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(path + says), std::string::npos) << e.what();
        }
    }
    std::filesystem::remove_all(dir);
}

TEST(Nff, HugeResolutionIsAnError) {
    EXPECT_NE(errorOf("v\nfrom 0 0 -5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 100000 8\n")
                  .find("bad.nff:7: 'resolution' must be at most 65536"),
              std::string::npos);
}

// Truncated and corrupted SPD files: each either parses or gives a
// SceneError that names the file and a line; nothing else escapes.
TEST(Nff, TruncatedAndCorruptedFilesFailCleanly) {
    std::mt19937_64 rng(99);
    for (const char* name : {"rings-2", "gears-2", "tetra-3"}) {
        std::ifstream f(std::string(RT_SCENE_DIR) + "/" + name + ".nff");
        const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        ASSERT_FALSE(text.empty());
        for (int i = 0; i < 150; ++i) {
            std::string t = text.substr(0, rng() % text.size());
            if (i % 2) {  // corrupt a few bytes too
                for (int k = 0; k < 3 && !t.empty(); ++k) t[rng() % t.size()] = "x.-e9 \n#"[rng() % 8];
            }
            try {
                parseNff(t, "cut.nff");
            } catch (const SceneError& e) {
                const std::string m = e.what();
                ASSERT_EQ(m.rfind("cut.nff:", 0), 0u) << m;
                ASSERT_EQ(m.find('\n'), std::string::npos) << m;
            }
        }
    }
}
