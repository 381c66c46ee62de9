#include "framebuffer/frame_buffer.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "process/spawn.h"

namespace rt {

FrameBufferUnit::FrameBufferUnit(sc_core::sc_module_name name, int index, int units, size_t pixels,
                                 Picos costPerContribution, int maxExp, bool progress, Picos quantum)
    : sc_module(name),
      in("in"),
      toController("to_controller"),
      toUnits("to_units"),
      index_(index),
      units_(units),
      cost_(costPerContribution),
      progress_(progress && index == 0),
      time_(quantum),
      maxExp_(maxExp),
      credit_(maxExp),
      expected_(size_t(index == 0 ? units : 0), 0),
      sums_(pixels > size_t(index) ? (pixels - size_t(index) + size_t(units) - 1) / size_t(units) : 0) {
    SC_METHOD(run);
}

void FrameBufferUnit::setLate(Picos late) {
    if (controller()) throw std::logic_error("unit 0 decides the frame's end: it cannot take its input late");
    late_ = late;
}

void FrameBufferUnit::finish(Picos now) {
    done_ = true;
    renderTime_ = now;
    if (progress_) std::fprintf(stderr, "\r%-60s\r", "");
    // The machine ends every other process; with nothing left to run, the
    // simulation returns (and may go on with the next frame: machine.h).
    if (onFinish_) onFinish_();
}

sc_core::sc_process_handle FrameBufferUnit::restart(bool progress, int frame) {
    progress_ = progress && index_ == 0;
    credit_ = Credit(maxExp_);
    std::fill(expected_.begin(), expected_.end(), 0);
    awaiting_ = -1;
    sampleDue_ = false;
    expect_.reset();
    sums_ = PixelSums(sums_.size());
    inputOrder_.restart();
    stats_ = {};
    done_ = false;
    dropCredit_ = false;
    renderTime_ = 0;
    trace_ = {};
    started_ = waiting_ = false;
    now_ = 0;
    return spawnMethod([this] { run(); }, *this, frame);
}

void FrameBufferUnit::accumulate(const Contribution& c) {
    const uint32_t local = c.pixel / uint32_t(units_);
    if (int(c.pixel % uint32_t(units_)) != index_ || local >= sums_.size())
        throw std::logic_error(std::string(name()) + ": a contribution for another unit's pixel " + std::to_string(c.pixel));
    stats_.digest += contributionDigest(c);
    sums_.add(local, c);
}

Picos FrameBufferUnit::take(Message& m) {
    auto fail = [&](const std::string& what) { throw std::logic_error(std::string(name()) + ": " + what); };
    switch (m.type) {
        case MsgType::Contributions: {
            const std::vector<Contribution>& cs = m.body().contributions;
            // The batch's sums, fetched together (a unit's pixels are spread
            // over its 16th of the image: each sum is out of cache).
            for (const Contribution& c : cs)
                if (c.pixel / uint32_t(units_) < sums_.size()) sums_.prefetch(c.pixel / uint32_t(units_));
            for (const Contribution& c : cs) accumulate(c);
            ++stats_.contributionMessages;
            stats_.contributions += cs.size();
            return cost_ * cs.size();
        }
        case MsgType::Credit:
            if (!controller()) fail("credit sent to a unit other than 0");
            if (dropCredit_) {  // the planted lost credit
                dropCredit_ = false;
                return 0;
            }
            ++stats_.creditMessages;
            credit_.add(m.body().credit);
            if (sampleDue_ && !m.body().sampleCredit.isZero()) sampleBack_.add(m.body().sampleCredit);
            for (const auto& [u, n] : m.body().unitCounts) expected_.at(u) += n;
            return 0;
        case MsgType::FbExpect:
            if (controller() || expect_) fail("unexpected fb_expect");
            expect_ = m.body().count;
            // Its fb_done must leave no earlier than the kernel's time (a
            // message is sent from its sender's time on): from now on it takes
            // every message when it arrives, and so is never behind the kernel
            // when it takes the last one.
            if (late_ > 0) inputOrder_.setLate(0, ~size_t(0));
            return 0;
        case MsgType::FbDone:
            if (!controller() || awaiting_ <= 0) fail("unexpected fb_done");
            --awaiting_;
            return 0;
        default:
            fail(std::string("unexpected ") + msgTypeName(m.type) + " message");
    }
    return 0;
}

// One activation of the unit's method process: it takes its input until it
// must let the kernel catch up (after a step) or wait for input, and arms its
// next activation for then.
void FrameBufferUnit::run() {
    if (!started_) {
        if (!begin()) return;
    } else if (waiting_) {
        waiting_ = false;
        inputOrder_.woke();
        if (late_ == 0) now_ = frameClock();  // (late, it goes on from its own time)
    }
    for (;;) {
        Picos next;
        const int best = inputOrder_.oldest(now_, next);  // ties go to the lower port: nodes, then units
        if (best < 0) {
            if (waitFor(next)) return;
            continue;
        }
        Message m = inLinks_[size_t(best)]->consume(now_);
        const Picos cost = take(m);
        traceTake(cost);
        now_ += cost;
        checkSimTime(now_, [this] { return name(); });
        stats_.busy += cost;
        if (cost) stats_.lastActive = now_;
        if (controller()) {
            tellSampleDone();
            if (endOfFrame()) return;
        } else {
            reportDone();
        }
        if (progress_) showProgress();
        if (time_.mustSync(now_, cost)) {
            time_.syncTo(now_);
            return;
        }
    }
}

// Its first activation: listens to the other units' ports (in the first
// frame); false if the frame is over already (nothing to trace at all).
bool FrameBufferUnit::begin() {
    started_ = true;
    if (!unitsListened_) {  // (the first frame's start, when the ports are bound)
        for (int i = 0; i < in.size(); ++i) {
            inLinks_.push_back(&asLink(*in[i]));
            inputOrder_.listen(int(inLinks_.size() - 1), inLinks_.back());
        }
        unitsListened_ = true;
    }
    if (late_ > 0) inputOrder_.setLate(late_, inLinks_.size() - 1);  // its last input is from unit 0
    now_ = frameClock();
    lastPrint_ = std::chrono::steady_clock::now();
    if (controller()) tellSampleDone();  // (a sample of no rays is done at once)
    if (controller() && credit_.isOne()) {
        finish(now_);
        return false;
    }
    return true;
}

// Unit 0, --sample-end credit: once the sample's credit is all back, its
// columns' lowest nodes are told, once.
void FrameBufferUnit::tellSampleDone() {
    if (!sampleDue_ || !(sampleBack_ == sampleTotal_)) return;
    sampleDue_ = false;
    if (tellColumns_.size() != toColumns_.size())
        throw std::logic_error(std::string(name()) + ": a sample's columns without a link to each");
    for (size_t c = 0; c < toColumns_.size(); ++c)
        if (tellColumns_[c]) toColumns_[c]->send(Message::sample({}), now_);
}

// No message has arrived by now_; the next arrives at `next` (~0: none
// known). Whether the process must return (it waits for input).
bool FrameBufferUnit::waitFor(Picos next) {
    // The next arrival is known and within the quantum (or, late, before
    // it: every message that arrives by then is in its links).
    if (late_ > 0 ? next != ~Picos(0) && time_.sees(next) : time_.mayIdleUntil(next)) {
        now_ = std::max(now_, next);
        return false;
    }
    if (inputOrder_.waitForInput(now_)) {  // also lets the kernel catch up with `now_`
        waiting_ = true;
        return true;
    }
    now_ = std::max(now_, frameClock());
    return false;
}

void FrameBufferUnit::traceTake(Picos cost) {
    if (!trace_.vcd) return;
    if (cost) {
        trace_.vcd->set(now_, trace_.busy, 1);
        trace_.vcd->set(now_ + cost, trace_.busy, 0);
    }
    trace_.vcd->set(now_ + cost, trace_.contributions, int64_t(stats_.contributions));
    if (trace_.credit >= 0) trace_.vcd->setReal(now_ + cost, trace_.credit, credit_.value());
}

// Unit 0: once the credit is whole, every contribution has been sent: it
// tells each other unit how many to expect, and the frame ends when all
// have answered. Whether the frame has ended.
bool FrameBufferUnit::endOfFrame() {
    if (awaiting_ < 0 && credit_.isOne()) {
        awaiting_ = units_ - 1;
        for (int u = 1; u < units_; ++u) toUnits[u - 1]->send(Message::fbExpect(expected_[size_t(u)]), now_);
    }
    if (awaiting_ != 0) return false;
    finish(now_);
    return true;
}

// Units 1..K-1: once all it was told to expect are accumulated, it says so, once.
void FrameBufferUnit::reportDone() {
    if (!expect_ || stats_.contributions < *expect_) return;
    if (stats_.contributions > *expect_) throw std::logic_error(std::string(name()) + ": more contributions than sent");
    if (now_ < frameClock())  // (setLate: it cannot be behind here)
        throw std::logic_error(std::string(name()) + ": fb_done sent before the kernel's time");
    toController->send(Message::fbDone(), now_);
    expect_.reset();
}

void FrameBufferUnit::showProgress() {
    const auto t = std::chrono::steady_clock::now();
    if (t - lastPrint_ > std::chrono::milliseconds(500)) {
        lastPrint_ = t;
        std::fprintf(stderr, "\rrtsim: %5.1f%% of the frame's rays done", 100.0 * credit_.value());
    }
}

Image assembleImage(sc_core::sc_vector<FrameBufferUnit>& units, int width, int height) {
    Image img(width, height);
    const uint32_t n = uint32_t(units.size());
    for (uint32_t p = 0; p < img.pixels.size(); ++p) img.pixels[p] = units[p % n].pixel(p);
    return img;
}

}  // namespace rt
