// Command-line options that choose a scene: an NFF file, or the built-in
// procedural scene of the paper's experiment with its parameters. Shared by
// rtref and rtsim so both read scenes the same way.
#pragma once
#include <string>

#include <CLI/CLI.hpp>

#include "procedural.h"
#include "scene.h"

namespace rt {

struct SceneOptions {
    std::string file;  // empty: the procedural scene
    ProceduralParams procedural;
    std::string axis = "x";
    std::string size;  // "WxH", empty: the scene's own resolution
    std::vector<double> lights;  // --light x y z, repeatable; empty: the defaults
    std::vector<double> eye, lookAt;  // empty: the defaults

    // `positional`: the scene file is a positional argument (rtref) rather
    // than --scene (rtsim).
    void addTo(CLI::App& app, bool positional);
    // Reads or builds the scene; throws SceneError on bad input.
    Scene load() const;
    // The --size value, or the scene's resolution.
    void imageSize(const Scene& scene, int& width, int& height) const;
    // That size as a message names it: "--size WxH", or the scene's
    // resolution where no --size was given (the user never typed one).
    std::string sizeNamed(int width, int height) const;
};

// "WxH" with positive integers; throws CLI::ValidationError otherwise.
void parseSize(const std::string& text, int& width, int& height);

// Each value a finite number (not nan or inf) of magnitude at most 1e9
// (kMaxSceneMagnitude): for coordinates, which CLI11 would otherwise take
// as they come.
CLI::Validator finiteNumber();

// Each of `flags` (x y z vectors: --eye, --look-at) given with exactly
// three numbers each time it appears in `args` (the command line, argv[0]
// first): under rtsim's rule that a flag's last value wins (TakeLast),
// CLI11 kept the last three of "--eye 1,2,3,4" and said nothing.
// Throws CLI::ValidationError naming the flag.
void checkTriples(const std::vector<std::string>& args, const std::vector<std::string>& flags);

// No argument "--flag=" with nothing after the '=': CLI11 takes the next
// argument as its value ("--sample-links= --mesh 2" said "got '--mesh'",
// "--image= --size 8x8" wrote an image named "--size"). Call it on the
// command line's arguments (without the program) before parsing.
void checkNoEmptyValues(const std::vector<std::string>& args);

// Every integer option of `app` (CLI11's types INT and UINT) takes decimal
// digits only, and every FLOAT one no hexadecimal: CLI11 reads integers as
// C's strtol in base 0 does, so that "--mesh 010" ran an 8 x 8 x 8 mesh and
// " -1" wrapped to 2^64 - 1, and numbers as strtod, "--speed 0x10" 16. Call
// it once every option is added.
void decimalNumbersOnly(CLI::App& app);

}  // namespace rt
