// What travels on a link or a frame-buffer port. Every message has a type and
// a size in bytes; the size is what the link's bandwidth is charged for.
#pragma once
#include <algorithm>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "channel/credit.h"
#include "ray_job.h"
#include "shape.h"

namespace rt {

enum class MsgType : uint8_t {
    Ray = 0, Contributions = 1, Credit = 2, LoadReport = 3, Slide = 4, Ack = 5,
    FbExpect = 6,  // frame-buffer unit 0 to unit u, at the end: how many contributions u must have
    FbDone = 7,    // unit u back to unit 0: it has accumulated them all
    Sample = 8,    // `sample`: the column's sampled work by position, from its lowest node through the sender
    Planes = 9,    // `sample`: the column's planes, from its top node down (and to columns without primary rays)
};
constexpr int kMsgTypes = 10;
const char* msgTypeName(MsgType t);

// Wire sizes (bytes). A ray: origin, direction, t0, tEnd, weight (doubles,
// 13 x 8), pixel 4, path 8, slot 4, depth 1, kind 1, credit exponent 2.
constexpr uint32_t kHeaderBytes = 8;  // type, length, source
constexpr uint32_t kRayBytes = 13 * 8 + 4 + 8 + 4 + 1 + 1 + 2;
constexpr uint32_t kContributionBytes = 4 + 8 + 4 + 3 * 8;  // pixel, path, slot, rgb
constexpr uint32_t kLoadReportBytes = 4 + 5 * 8;            // round, end, busy, wait, backlog, column sum
constexpr uint32_t kSlideBytes = 8 + 4;                     // new boundary, object count (+ the objects)
constexpr uint32_t kAckBytes = 8;                           // the boundary taken
constexpr uint32_t kUnitCountBytes = 2 + 4;                 // Credit: a frame-buffer unit and a count
constexpr uint32_t kFbExpectBytes = 8;                      // the count
constexpr uint32_t kHandedBytes = 4 + 2;                    // a primary ray handed over: pixel, credit exponent
constexpr uint32_t kValueBytes = 8;                         // Sample, Planes: per bin, per plane (a double)

// The smallest message each kind of link carries, which sets how soon a
// message not yet sent can arrive (the lookahead, MachineConfig::lookahead;
// Link::send refuses a smaller one). A mesh link carries rays (a message
// holds at least one) and, under a dynamic balancing policy, load reports,
// slides and acks; the frame-buffer ports and the links between units
// carry contributions, credit, FbExpect and FbDone (a header alone).
static_assert(kAckBytes <= kSlideBytes && kAckBytes <= kLoadReportBytes, "the ack is the smallest control message");
constexpr uint32_t smallestMeshMessage(bool control) { return kHeaderBytes + (control ? kAckBytes : kRayBytes); }
constexpr uint32_t kSmallestFbMessage = kHeaderBytes;

// Bytes of one object on the wire: id, material, kind, then its geometry.
uint32_t objectBytes(const Shape& s);

// A primary ray not yet generated: its pixel and its credit exponent.
struct Primary {
    uint32_t pixel;
    uint16_t exp;
};
using HandedPrimaries = std::vector<Primary>;

// One ray on the wire, with its credit 2^-creditExp: what kRayBytes counts,
// the job without its ray's reciprocal direction. The receiver computes that
// again as Ray's constructor does (Ray::reciprocal), so the ray it
// traces is the sender's to the bit; a link holding a message per ray in
// flight keeps 112 bytes each instead of 144 (doc/exploration.md).
struct RayItem {
    Vec3 o, d;
    double t0 = 0, tEnd = 0;
    Vec3 weight{1.0};
    uint32_t pixel = 0;
    PathKey key;
    uint8_t depth = 0;
    RayKind kind = RayKind::Primary;
    uint16_t creditExp = 0;

    RayItem() = default;
    RayItem(const RayJob& j, uint16_t exp) { set(j, exp); }
    // The job and its credit, written field by field (not built and copied).
    void set(const RayJob& j, uint16_t exp) {
        o = j.ray.o;
        d = j.ray.d;
        t0 = j.t0;
        tEnd = j.tEnd;
        weight = j.weight;
        pixel = j.pixel;
        key = j.key;
        depth = j.depth;
        kind = j.kind;
        creditExp = exp;
    }
    // The job, written field by field into `j` (not built and copied: a
    // copy of a job just written by parts stalls on the parts).
    void fill(RayJob& j) const {
        j.ray.o = o;
        j.ray.d = d;
        j.ray.inv = Ray::reciprocal(d);
        j.t0 = t0;
        j.tEnd = tEnd;
        j.weight = weight;
        j.pixel = pixel;
        j.key = key;
        j.depth = depth;
        j.kind = kind;
    }
};
static_assert(sizeof(RayItem) == 112, "a ray on the wire: 13 doubles, pixel, path key, depth, kind, credit");
// A batch of rays (--ray-batch), collected by a node or received.
using RayList = std::vector<RayItem>;

// What the messages other than a single ray carry, behind one pointer (rays
// are most of the messages, and a link holds a message by value).
struct MessageBody {
    RayList batch;                             // Ray: a batch of rays (--ray-batch)
    std::vector<Contribution> contributions;   // Contributions
    Credit credit;                             // Credit
    Credit sampleCredit;                       // Credit (--sample-end credit): the part of it the sample's rays gave back
    // Credit, with more than one frame-buffer unit: contributions sent to
    // each unit but 0 since the node last returned credit (unit, count).
    std::vector<std::pair<uint16_t, uint32_t>> unitCounts;
    uint64_t count = 0;                        // FbExpect
    int32_t interval = 0;                      // LoadReport: the round
    uint64_t end = 0, busy = 0, wait = 0;      // LoadReport: the span's end, busy and wait time (ps)
    uint64_t backlog = 0;                      // LoadReport: work waiting at the end (ps)
    double sum = 0;                            // LoadReport: the column's demand up to the reporter (policy.h)
    double boundary = 0;                       // Slide, Ack: the boundary's new coordinate
    std::vector<Shape> objects;                // Slide: the objects of the moved slab
    std::vector<double> values;                // Sample: work per bin (ps); Planes: the inner planes (none: held)
    HandedPrimaries primaries;                 // Slide (`sample`): the slab's primary rays not yet generated
};

// 128 bytes: two cache lines. A link holds every message sent on it until
// its receiver takes it, and on balls-4 at 512x512 a link out of the node
// that generates the primary rays holds up to 126,000 at once (its output
// buffer in the modelled machine): most messages are written to memory
// and read back long after, so their size is what a run moves through
// memory (doc/exploration.md, "Where rtsim's time goes").
struct Message {
    // Ray: one ray inline, so the usual message (--ray-batch 1) is one
    // block of plain bytes that a link moves along (a container holding it
    // inline moved it through a library copy at every move), not a message
    // and a heap block of its own that the receiver reads long after
    // another node wrote it; or a batch, whose rays are all in the body's
    // `batch` (then `ray` is not used).
    RayItem ray;
    MsgType type = MsgType::Ray;
    // A ray of `sample`'s sample under --sample-end credit: it goes on the
    // link's control lane, ahead of the other rays (link.h).
    bool priority = false;

    Message() = default;
    // A message of one ray, the job's with its credit, written in place.
    Message(const RayJob& j, uint16_t creditExp) { ray.set(j, creditExp); }

    // The other kinds of message, each with what it carries.
    static Message rays(RayList batch) {  // a batch of rays (--ray-batch)
        Message m;
        m.body().batch = std::move(batch);
        return m;
    }
    static Message contributions(std::vector<Contribution> cs) {
        Message m(MsgType::Contributions);
        m.body().contributions = std::move(cs);
        return m;
    }
    // Credit back to unit 0, with the contributions sent to each other unit
    // since the last (frame_buffer.h).
    static Message credit(const Credit& c, std::vector<std::pair<uint16_t, uint32_t>> unitCounts, const Credit& sample = {}) {
        Message m(MsgType::Credit);
        m.body().credit = c;
        if (!sample.isZero()) m.body().sampleCredit = sample;
        m.body().unitCounts = std::move(unitCounts);
        return m;
    }
    static Message loadReport(int32_t round, uint64_t end, uint64_t busy, uint64_t wait, uint64_t backlog, double sum) {
        Message m(MsgType::LoadReport);
        MessageBody& r = m.body();
        r.interval = round;
        r.end = end;
        r.busy = busy;
        r.wait = wait;
        r.backlog = backlog;
        r.sum = sum;
        return m;
    }
    static Message slide(double boundary, std::vector<Shape> objects) {
        Message m(MsgType::Slide);
        m.body().boundary = boundary;
        m.body().objects = std::move(objects);
        return m;
    }
    static Message ack(double boundary) {
        Message m(MsgType::Ack);
        m.body().boundary = boundary;
        return m;
    }
    static Message fbExpect(uint64_t count) {
        Message m(MsgType::FbExpect);
        m.body().count = count;
        return m;
    }
    static Message fbDone() { return Message(MsgType::FbDone); }
    static Message sample(std::vector<double> bins) { return valued(MsgType::Sample, std::move(bins)); }
    static Message planes(std::vector<double> planes) { return valued(MsgType::Planes, std::move(planes)); }

    bool batched() const { return body_ && !body_->batch.empty(); }
    size_t rayCount() const { return batched() ? body_->batch.size() : 1; }
    const RayItem& rayAt(size_t i) const { return batched() ? body_->batch[i] : ray; }
    // A batch's list, taken from the message (empty if it holds one ray).
    RayList takeBatch() { return body_ ? std::move(body_->batch) : RayList{}; }

    // The rest (made when first written; a message without one reads as empty).
    MessageBody& body() {
        if (!body_) body_ = std::make_unique<MessageBody>();
        return *body_;
    }
    const MessageBody& body() const {
        static const MessageBody empty;
        return body_ ? *body_ : empty;
    }

    uint32_t bytes() const {
        switch (type) {
            case MsgType::Ray: return kHeaderBytes + uint32_t(rayCount()) * kRayBytes;
            case MsgType::Contributions: return kHeaderBytes + uint32_t(body().contributions.size()) * kContributionBytes;
            case MsgType::Credit:
                return kHeaderBytes + body().credit.bytes() + (body().sampleCredit.isZero() ? 0 : body().sampleCredit.bytes()) +
                       uint32_t(body().unitCounts.size()) * kUnitCountBytes;
            case MsgType::LoadReport: return kHeaderBytes + kLoadReportBytes;
            case MsgType::Slide: {
                uint32_t b = kHeaderBytes + kSlideBytes;
                for (const Shape& s : body().objects) b += objectBytes(s);
                return b + uint32_t(body().primaries.size()) * kHandedBytes;
            }
            case MsgType::Ack: return kHeaderBytes + kAckBytes;
            case MsgType::FbExpect: return kHeaderBytes + kFbExpectBytes;
            case MsgType::FbDone: return kHeaderBytes;
            // (a Planes message with no plane still carries its count: at least an ack's bytes)
            case MsgType::Sample:
            case MsgType::Planes: return kHeaderBytes + std::max<uint32_t>(kAckBytes, uint32_t(body().values.size()) * kValueBytes);
        }
        return kHeaderBytes;
    }

private:
    explicit Message(MsgType t) : type(t) {}
    static Message valued(MsgType t, std::vector<double> v) {
        Message m(t);
        m.body().values = std::move(v);
        return m;
    }
    std::unique_ptr<MessageBody> body_;
};
static_assert(sizeof(Message) == 128, "a message: a ray, its type and the body's pointer");

// Load reports, slides, acks and `sample`'s gather: the balancing protocol's
// messages, which a link's control lane carries (link.h).
inline bool isControl(MsgType t) {
    return t == MsgType::LoadReport || t == MsgType::Slide || t == MsgType::Ack || t == MsgType::Sample ||
           t == MsgType::Planes;
}

// A step's sends, in order: each a destination (a link direction, or kDirs
// + unit for a frame-buffer unit) and its message.
using Outbox = std::vector<std::pair<int, Message>>;

}  // namespace rt
