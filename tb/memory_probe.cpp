// memory_probe: what one load costs this machine as the memory it reaches
// grows, and what a fresh page costs to touch. scripts/bench_misses.py
// counts a message's cache misses in a model of a cache; these figures
// are what such a miss costs here, and where this machine's cache really
// ends (scripts/bench_memory.py, doc/benchmarks/memory.md).
//
// For each size: a region of that many MiB, fresh from the system, backed
// by huge (2 MiB) or small pages as asked (madvise); the time to write it
// once (the kernel zeroes every page as it is first touched), then a chase
// through its 64-byte lines in one random cycle (each load's address is
// the load before's value, so no two overlap and no prefetcher can guess
// the next), the mean time of a load. One JSON object per size, a line
// each, on standard output.
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace {

constexpr size_t kLine = 64, kHuge = size_t(2) << 20;
volatile uint64_t chaseEnd;  // where a chase ended: read, so that the chase is not optimised away

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// A region of `bytes` on 2 MiB boundaries, its pages of the kind asked.
struct Region {
    char* base = nullptr;
    void* mapped = MAP_FAILED;
    size_t length = 0;
    Region(size_t bytes, bool huge) : length(bytes + kHuge) {
        mapped = mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (mapped == MAP_FAILED) throw std::runtime_error("cannot map " + std::to_string(bytes >> 20) + " MiB");
        base = reinterpret_cast<char*>((reinterpret_cast<uintptr_t>(mapped) + kHuge - 1) & ~uintptr_t(kHuge - 1));
        madvise(base, bytes, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
    }
    ~Region() {
        if (mapped != MAP_FAILED) munmap(mapped, length);
    }
    Region(const Region&) = delete;
    Region& operator=(const Region&) = delete;
};

nlohmann::json probe(double mib, bool huge, uint64_t loads, uint64_t seed) {
    const size_t bytes = size_t(mib * 1024 * 1024) / kLine * kLine, lines = bytes / kLine;
    Region r(bytes, huge);
    const auto touched = std::chrono::steady_clock::now();
    std::memset(r.base, 1, bytes);
    const double touch = secondsSince(touched);
    // One cycle through every line (Sattolo's shuffle), each line holding
    // the next one's offset.
    std::vector<uint32_t> next(lines);
    for (size_t i = 0; i < lines; ++i) next[i] = uint32_t(i);
    std::mt19937_64 rng(seed);
    for (size_t i = lines - 1; i > 0; --i) std::swap(next[i], next[std::uniform_int_distribution<size_t>(0, i - 1)(rng)]);
    for (size_t i = 0; i < lines; ++i) *reinterpret_cast<uint64_t*>(r.base + i * kLine) = uint64_t(next[i]) * kLine;
    uint64_t at = 0;
    for (uint64_t k = 0; k < std::min<uint64_t>(lines, loads); ++k) at = *reinterpret_cast<const uint64_t*>(r.base + at);
    const auto chased = std::chrono::steady_clock::now();
    for (uint64_t k = 0; k < loads; ++k) at = *reinterpret_cast<const volatile uint64_t*>(r.base + at);
    const double chase = secondsSince(chased);
    chaseEnd = at;
    return {{"mib", mib},
            {"pages", huge ? "huge" : "small"},
            {"ns_per_load", chase * 1e9 / double(loads)},
            {"touch_ms_per_mib", touch * 1e3 / mib}};
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"memory_probe: the time of a load by the memory it reaches, and of a fresh page's first touch"};
    std::vector<double> sizes{1, 4, 16, 64, 256, 1024};
    std::string pages = "huge";
    uint64_t loads = 20'000'000, seed = 1;
    app.add_option("--mib", sizes, "region sizes, MiB")->check(CLI::Range(0.0625, 65536.0))->delimiter(',');
    app.add_option("--pages", pages, "huge (2 MiB, madvise) or small")->check(CLI::IsMember({"huge", "small"}));
    app.add_option("--loads", loads, "loads timed per size")->check(CLI::Range(uint64_t(1000), uint64_t(1) << 34));
    app.add_option("--seed", seed, "the cycle's shuffle");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {  // (one line, exit 2: bad input)
        std::fprintf(stderr, "memory_probe: %s\n", e.what());
        return 2;
    }
    const double memory = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) / (1 << 20);
    for (double mib : sizes)
        if (mib > memory / 2) {
            std::fprintf(stderr, "memory_probe: --mib %g: more than half of this machine's %.0f MiB\n", mib, memory);
            return 2;
        }
    try {
        for (double mib : sizes) std::printf("%s\n", probe(mib, pages == "huge", loads, seed).dump().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "memory_probe: %s\n", e.what());
        return 1;
    }
    return 0;
}
