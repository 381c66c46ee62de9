// What travels on a link or a frame-buffer port. Every message has a type and
// a size in bytes; the size is what the link's bandwidth is charged for.
#pragma once
#include <cstdint>
#include <vector>

#include "credit.h"
#include "ray_job.h"

namespace rt {

enum class MsgType : uint8_t { Ray = 0, Contributions = 1, Credit = 2 };
constexpr int kMsgTypes = 3;
const char* msgTypeName(MsgType t);

// Wire sizes (bytes). A ray: origin, direction, t0, tEnd, weight (doubles,
// 13 x 8), pixel 4, path 8, slot 4, depth 1, kind 1, credit exponent 2.
constexpr uint32_t kHeaderBytes = 8;  // type, length, source
constexpr uint32_t kRayBytes = 13 * 8 + 4 + 8 + 4 + 1 + 1 + 2;
constexpr uint32_t kContributionBytes = 4 + 8 + 4 + 3 * 8;  // pixel, path, slot, rgb

struct Message {
    MsgType type = MsgType::Ray;
    RayJob ray;                                // Ray
    uint16_t creditExp = 0;                    // Ray: its credit is 2^-creditExp
    std::vector<Contribution> contributions;   // Contributions
    Credit credit;                             // Credit

    uint32_t bytes() const {
        switch (type) {
            case MsgType::Ray: return kHeaderBytes + kRayBytes;
            case MsgType::Contributions: return kHeaderBytes + uint32_t(contributions.size()) * kContributionBytes;
            case MsgType::Credit: return kHeaderBytes + credit.bytes();
        }
        return kHeaderBytes;
    }
};

}  // namespace rt
