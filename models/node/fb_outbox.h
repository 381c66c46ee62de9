// What a node owes the frame buffer: its contributions, batched per unit
// (pixel p belongs to unit p mod K; --fb-batch per message), and the credit
// of the rays that ended here, returned to unit 0 behind them on the same
// FIFO ports (credit.h, frame_buffer.h). Plain C++.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "channel/credit.h"
#include "base/mesh_geometry.h"
#include "channel/message.h"

namespace rt {

class FrameBufferOutbox {
public:
    FrameBufferOutbox(int units, int batch) : pending_(size_t(units)), sentSince_(size_t(units), 0), batch_(batch) {}

    // The outbox destination of unit u.
    static int target(int unit) { return kDirs + unit; }

    // Credit: the node's share before the start, and what rays ending here give back.
    void setCredit(const Credit& c) {
        credit_ = c;
        sampleCredit_ = c;
        sampleCredit_.clear();
        holds_ = !credit_.isZero();
        holdsSample_ = false;
    }
    void addCredit(int e, uint64_t k = 1) {
        credit_.add(e, k);
        holds_ = holds_ || k > 0;
    }
    // --sample-end credit: what a ray of the sample gives back, returned
    // within the same credit messages and counted apart by unit 0.
    void addSampleCredit(int e, uint64_t k = 1) {
        sampleCredit_.add(e, k);
        holdsSample_ = holdsSample_ || k > 0;
    }

    // A step's contributions into their units' batches; the batches they
    // fill go into the outbox.
    void add(const std::vector<Contribution>& cs, Outbox& out) {
        for (const Contribution& c : cs) {
            pending_[size_t(unitOf(c))].push_back(c);
            ++count_;
        }
        for (const Contribution& c : cs) {  // full batches leave at the end of the step
            const int u = unitOf(c);
            if (pending_[size_t(u)].size() >= size_t(batch_)) send(u, out);
        }
    }
    // Before the node waits: every part batch, then its returned credit to
    // unit 0, with how many contributions it has sent to each other unit
    // since it last returned credit. Unit 0's own contributions travel
    // ahead of the credit on the same port; for the others, unit 0 checks
    // the counts with each unit once the credit is whole. Throws
    // std::logic_error if contributions went without credit, naming `who()`
    // (asked only then: a node's name is a cold read on a large mesh, and a
    // string built at every flush was a tenth of the flush's instructions).
    template <class Who>
    void flush(Outbox& out, const Who& who) {
        if (!flushAll(out)) throw std::logic_error(std::string(who()) + ": contributions sent without credit to cover them");
    }

    bool owes() const { return count_ || holdsCredit(); }  // contributions or credit not yet sent
    size_t contributions() const { return count_; }
    // (Kept as flags: a node asks after every step, and the credit's words
    // are a cold read on a large mesh. Credit added is never zero: its
    // whole part does not wrap.)
    bool holdsCredit() const { return holds_ || holdsSample_; }
    bool holdsSampleCredit() const { return holdsSample_; }

private:
    int unitOf(const Contribution& c) const { return int(c.pixel % uint32_t(pending_.size())); }
    void send(int unit, Outbox& out);  // the unit's batch, now
    bool flushAll(Outbox& out);  // flush; false if contributions went without credit

    std::vector<std::vector<Contribution>> pending_;  // per unit: contributions not yet sent
    size_t count_ = 0;                                // in all of them
    bool holds_ = false, holdsSample_ = false;        // credit_, sampleCredit_ not zero
    std::vector<uint32_t> sentSince_;  // per unit: contributions sent since the last credit return
    bool sentAny_ = false;             // any of them not zero
    int batch_;
    Credit credit_;  // returned credit not yet sent
    Credit sampleCredit_;  // of it apart, the sample's (--sample-end credit)
};

}  // namespace rt
