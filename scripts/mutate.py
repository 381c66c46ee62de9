#!/usr/bin/python3
"""Planted timing bugs: does the test suite notice?

Each mutant below is one small, plausible timing bug in models/ (a link's
slot returned at the wrong time, serialisation dropped, a cost not charged,
an override ignored, a message's size wrong). The script copies the tracked
sources to a work directory, checks that the suite passes there unchanged,
then plants the mutants one at a time, rebuilds, runs the suite and
reports which tests failed. A mutant the suite misses is a cost the tests
cannot see; the script exits 1 if there is any.

  /usr/bin/python3 scripts/mutate.py            # every mutant; table to out/results/mutate.md
  /usr/bin/python3 scripts/mutate.py --doc      # to doc/results/mutate.md and doc/robustness.md
  /usr/bin/python3 scripts/mutate.py --only fb-cost-dropped,no-latency   # table to --work only
  /usr/bin/python3 scripts/mutate.py --check    # every mutant still fits the code (a test)

The work directory (--work) is the script's own: it is made with a mark
file, and a folder that holds anything without that mark is refused
rather than emptied."""
import argparse
import os
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import RESULTS, ROOT, publish_table  # noqa: E402

# The timing oracles' tests (tb/tests/test_timing.cpp): the table says
# whether the rest of the suite would have caught each bug without them.
ORACLES = ("LinkOracle", "RayAcrossEmptyNodes", "FrameBufferOracle", "SlideOracle")

# (name, file, exact text (found exactly once), replacement, what the bug is)
MUTANTS = [
    ("slot-back-at-once", "models/channel/link.cpp",
     "return l.takenAt(l.wired - l.slots) + params_.latency;", "return l.takenAt(l.wired - l.slots);",
     "a consumed message's flow-control slot is free at once, not one latency later"),
    ("slot-back-late", "models/channel/link.cpp",
     "return l.takenAt(l.wired - l.slots) + params_.latency;", "return l.takenAt(l.wired - l.slots) + 2 * params_.latency;",
     "the slot comes back two latencies after the message is consumed"),
    ("slot-never-waited-for", "models/channel/link.cpp",
     "const Picos ready = std::max(sent, slot);", "const Picos ready = sent + 0 * slot;",
     "a message waiting for a slot goes on the wire as if one were free"),
    ("wire-overlap", "models/channel/link.cpp",
     "wireFree_ = start + transfer;", "wireFree_ = start;",
     "serialisation dropped: messages overlap on the wire"),
    ("no-transfer-time", "models/channel/link.cpp",
     "const Picos arrival = start + transfer + params_.latency;", "const Picos arrival = start + 0 * transfer + params_.latency;",
     "a message arrives one latency after it starts, whatever its size"),
    ("no-latency", "models/channel/link.cpp",
     "const Picos arrival = start + transfer + params_.latency;", "const Picos arrival = start + transfer;",
     "the link's latency is not added"),
    ("bandwidth-in-bits", "models/channel/link_params.h",
     "return double(bytes) * 1e12 / bandwidth;", "return double(bytes) * 1e12 / (8 * bandwidth);",
     "the bandwidth read as bits per second: transfers 8 times too short"),
    ("link-engine-free", "models/config/machine_config.cpp",
     "        p.engine = costsOf(from).send;\n        p.latency", "        p.engine = 0;\n        p.latency",
     "with --hop-handling link the sending engine's handling takes no time on the wire"),
    ("link-receive-free", "models/config/machine_config.cpp",
     "p.latency += costsOf(neighbour(from, dir)).recv;", "p.latency += 0;",
     "with --hop-handling link the receiving engine's handling adds nothing to the latency"),
    ("resplit-ignores-where-work-happened", "models/balance/frame_forecast.cpp",
     'if (node.contains("work_by_position")) {', "if (false) {",
     "resplit spreads each node's busy time evenly over its box, as before the work profile"),
    ("forecast-ignores-cut-rays", "models/balance/frame_forecast.cpp",
     "c.perCrossing = c.faceRays > 0 ? c.faceNs / c.faceRays : 0;", "c.perCrossing = 0;",
     "resplit's forecast charges nothing for the rays a plane cuts (thin boxes look free)"),
    ("forecast-passes-free", "models/balance/frame_forecast.cpp",
     "busy[size_t(l.to)][size_t(j)] += l.rays * 2 * columns_[size_t(l.to)].perCrossing;",
     "busy[size_t(l.to)][size_t(j)] += 0;",
     "resplit's forecast charges nothing for the rays passed on where columns' planes differ"),
    ("search-ignores-lateral-links", "models/balance/frame_forecast.cpp",
     "for (const std::vector<double>& below : c.lateralBelow) rays = std::max(rays, below[size_t(j)] - below[size_t(i)]);",
     "",
     "resplit's searches ignore the rays a node sends to neighbouring columns (a long part's lateral link looks free)"),
    ("columns-own-planes-pass-freely", "models/balance/between_frames.cpp",
     "const bool linkBound = t.passes > 0 && t.linkNs >= t.nodeNs;", "const bool linkBound = false;",
     "resplit takes columns' own planes for any forecast edge over aligned ones, even where the links are the frame"),
    ("work-placed-past-the-hit", "models/node/node.cpp",
     "span.where = w.job.ray.at(0.5 * (t0 + stop))[ax];",
     "span.where = w.job.ray.at(0.5 * (t0 + std::min(w.job.tEnd, box.span.hi)))[ax];",
     "a ray's work is recorded at the middle of its way through the box, past where it hit"),
    ("grid-over-the-whole-box", "sw/grid.cpp",
     ": UniformGrid(objects, box, occupiedPart(objects, box)) {}", ": UniformGrid(objects, box, box) {}",
     "a region's grid spans its whole box, not the part its objects occupy"),
    ("empty-grid-walked", "sw/grid.cpp",
     "    if (objects_.empty()) return best;", "",
     "a box with no objects walks its grid's empty cells"),
    ("forecast-without-tandem", "models/balance/frame_forecast.cpp",
     "    f.frameNs = std::max({f.nodeNs, f.linkNs, kTandem * std::min(f.nodeNs, f.linkNs)});",
     "    f.frameNs = std::max(f.nodeNs, f.linkNs);",
     "the forecast's frame is the dearer of node and link even where the two are close"),
    ("grid-part-flat", "sw/grid.cpp",
     "        if (hi - lo < cell) {", "        if (false) {",
     "a lone polygon's grid part is as thin as the polygon"),
    ("left-messages-wait-uncounted", "models/channel/link.cpp",
     "            if (l.backlog[i].sent < end) stats_.slotWait += end - l.backlog[i].sent;  // still waiting for a slot",
     "",
     "a message still waiting for a slot at the frame's end does not count its wait"),
    ("resplit-moves-for-any-gain", "models/balance/between_frames.cpp",
     "ns < (1 - kMinForecastGain) * c.heldNs", "ns < c.heldNs",
     "resplit moves the planes for any forecast gain, however small"),
    ("primaries-before-the-box-is-there", "models/node/node_balance.cpp",
     "    if (!startTargets_) return false;", "    return false;",
     "a re-split frame's nodes generate primary rays before their faces reach their targets"),
    ("moves-cost-nothing", "models/balance/between_frames.cpp",
     "            const double ns = t.frameNs + moveNs(r, m, now, planes);", "            const double ns = t.frameNs;",
     "resplit forecasts a move without what getting to its planes costs (slabs passed along chains)"),
    ("sample-planes-not-moved", "models/balance/balance_sample.cpp",
     "    g.adopt = !g.planes.empty();", "    g.adopt = false;",
     "sample gathers and splits but the faces never move to the planes"),
    ("sample-moves-however-late", "models/balance/balance_sample.cpp",
     "    if (!planes.empty() && !samplePays(g.sum, dearestPart(g.sum, planes), double(now))) planes.clear();", "",
     "sample's top node moves the column however late its sum comes, even where the move cannot pay"),
    ("sample-primaries-stay", "models/node/node_balance.cpp",
     "    if (sample_) slide.body().primaries = input_.handOver(", "    if (false) slide.body().primaries = input_.handOver(",
     "sample's slabs leave their primary rays with the giver, which generates them for a box it no longer has"),
    ("relay-refuses-empty-slabs", "models/balance/balance_agent.cpp",
     "(policy_->relays() && !(inSlab > 0))", "(false && !(inSlab > 0))",
     "relay's guard counts a slab with no recorded work as returning nothing, as slide's does: work stops at the second box"),
    ("relay-load-saturates", "models/balance/policy_relay.cpp",
     "const double mine = q.mine.demand(), theirs = q.theirs.demand();",
     "const double mine = q.mine.load(), theirs = q.theirs.load();",
     "relay takes the paper's load, which saturates at 1, instead of demand"),
    ("sample-not-first", "models/node/primary_queue.h",
     "return sampleWidth_ && inSample(pixel) ? 0 : 1;", "return 1;",
     "a node generates its primary rays in the host's order: the sample is not first"),
    ("sample-fed-by-every-neighbour", "models/machine/machine.cpp",
     "feeder[size_t(g.columnOf(n))] == opposite(d);", "feeder[size_t(g.columnOf(n))] != -1;",
     "a column that generates no primary rays gets planes from every neighbouring column, not from one"),
    ("start-moves-stop-at-the-box", "models/balance/balance_agent.cpp",
     "    if (!hold_) return;\n    const Box& b = host_.box();", "    return;\n    const Box& b = host_.box();",
     "a plane whose target lies past the next box stops at that box's edge"),
    ("no-send-cost", "models/node/cost_model.h",
     "p[kSend] = sends * costs_.send;", "p[kSend] = 0 * sends * costs_.send;",
     "handling an outgoing message costs nothing"),
    ("no-recv-cost", "models/node/cost_model.h",
     "p[kReceive] = recvs * costs_.recv;", "p[kReceive] = 0 * recvs * costs_.recv;",
     "handling an incoming message costs nothing"),
    ("no-raygen-cost", "models/node/cost_model.h",
     "generated * costs_.rayGen;", "0 * generated * costs_.rayGen;",
     "generating a primary ray costs nothing"),
    ("no-sphere-test-cost", "models/node/cost_model.h",
     "p[size_t(k)] = (c.tests[k] - before.tests[k]) * costs_.test[k];",
     "p[size_t(k)] = (k == 0 ? 0 : (c.tests[k] - before.tests[k]) * costs_.test[k]);",
     "a sphere intersection test costs nothing"),
    ("no-cone-test-cost", "models/node/cost_model.h",
     "p[size_t(k)] = (c.tests[k] - before.tests[k]) * costs_.test[k];",
     "p[size_t(k)] = (k == 2 ? 0 : (c.tests[k] - before.tests[k]) * costs_.test[k]);",
     "a cone (cylinder) intersection test costs nothing"),
    ("no-voxel-step-cost", "models/node/cost_model.h",
     "p[kVoxelSteps] = (c.voxelSteps - before.voxelSteps) * costs_.voxelStep;", "p[kVoxelSteps] = 0 * costs_.voxelStep;",
     "a 3D-DDA voxel step costs nothing"),
    ("no-shade-cost", "models/node/cost_model.h",
     "p[kShading] = (c.shadings - before.shadings) * costs_.shade;", "p[kShading] = 0 * costs_.shade;",
     "shading a hit costs nothing"),
    ("speed-ignored", "models/node/cost_model.h",
     "if (speed_ == 1.0) return ps;", "if (speed_ > 0) return ps;",
     "a node's speed factor is ignored"),
    ("rebuild-cost-dropped", "models/node/cost_model.h",
     "return atSpeed(objects * rebuild_);", "return atSpeed(0 * objects * rebuild_);",
     "a slide's grid update costs nothing per object moved"),
    ("ack-recv-free", "models/node/node_balance.cpp",
     "++stats_.acks;\n        finishControlStep(1, 0);",
     "++stats_.acks;\n        finishControlStep(0, 0);",
     "handling a slide's acknowledgement costs nothing"),
    ("slab-recv-free", "models/node/node_balance.cpp",
     "finishControlStep(1, moved);", "finishControlStep(0, moved);",
     "taking a slide's message costs nothing"),
    ("fb-cost-dropped", "models/framebuffer/frame_buffer.cpp",
     "return cost_ * cs.size();", "return 0 * cost_ * cs.size();",
     "the frame buffer accumulates contributions for free"),
    ("fb-cost-per-message", "models/framebuffer/frame_buffer.cpp",
     "return cost_ * cs.size();", "return cost_ + 0 * cs.size();",
     "the frame buffer charges per message, not per contribution"),
    ("fb-time-not-advanced", "models/framebuffer/frame_buffer.cpp",
     "        now_ += cost;\n", "        now_ += 0 * cost;\n",
     "the frame buffer counts its busy time but does not spend it"),
    ("ray-batch-as-one-ray", "models/channel/message.h",
     "kHeaderBytes + uint32_t(rayCount()) * kRayBytes;", "kHeaderBytes + 0 * uint32_t(rayCount()) + kRayBytes;",
     "a batch of rays is as many bytes on the wire as one ray"),
    ("contribution-batch-as-one", "models/channel/message.h",
     "kHeaderBytes + uint32_t(body().contributions.size()) * kContributionBytes;",
     "kHeaderBytes + 0 * uint32_t(body().contributions.size()) + kContributionBytes;",
     "a batch of contributions is as many bytes as one"),
    ("slide-objects-weightless", "models/channel/message.h",
     "for (const Shape& s : body().objects) b += objectBytes(s);",
     "for (const Shape& s : body().objects) b += 0 * objectBytes(s);",
     "a slide's objects add no bytes to its message"),
    ("link-override-ignored", "models/config/machine_config.cpp",
     "return it == linkOverride.end() ? link : it->second;", "return it == linkOverride.end() ? link : link;",
     "per-link overrides are ignored"),
    ("node-speed-override-ignored", "models/config/machine_config.cpp",
     "return it == nodeSpeed.end() ? speed : it->second;", "return it == nodeSpeed.end() ? speed : speed;",
     "per-node speeds are ignored"),
    ("node-costs-override-ignored", "models/config/machine_config.cpp",
     "return it == nodeCosts.end() ? costs : it->second;", "return it == nodeCosts.end() ? costs : costs;",
     "per-node cost sets are ignored"),
    # The links' own figures in the report (issue 13): what a user reads to
    # find the hot link.
    ("link-latency-from-ready", "models/channel/link.cpp",
     ".add(t - head.sent);", ".add(t - head.ready);",
     "a message's latency counted from when it had a slot, not from when it was sent"),
    ("link-slot-wait-to-start", "models/channel/link.cpp",
     "stats_.slotWait += std::min(m.ready, upTo) - m.sent;", "stats_.slotWait += std::min(m.start, upTo) - m.sent;",
     "the time waiting for the wire counted as waiting for a slot too"),
    ("link-wire-busy-without-headers", "models/channel/link.cpp",
     "byType_[size_t(w.type)].wire += transfer;", "byType_[size_t(w.type)].wire += transferTime(w.bytes - 8);",
     "a link's busy time leaves out each message's header"),
    ("buffer-high-water-stops-a-slot-short", "models/channel/link.h",
     "return distributions_ && stats_.bufferHighWater < l.slots;",
     "return distributions_ && stats_.bufferHighWater + 1 < l.slots;",
     "a link stops counting its buffer's high-water mark one short of its slots"),
    ("unconsumed-not-counted-on-the-wire", "models/channel/link.cpp",
     "if (listener_) ++listener_->buffered;", "(void)0;",
     "a receiver's count of messages on its links misses those going on the wire (its queue depth reads low)"),
    ("vcd-wire-held-late", "models/channel/link.cpp",
     "v.step(start + transfer, trace_.wire, -1);", "v.step(start + transfer + 1, trace_.wire, -1);",
     "the VCD shows the wire busy 1 ps longer than it was"),
    ("pass-not-counted-from-batch", "models/node/node_input.h",
     "w.take(received_[receivedNext_++], false, receivedFrom_);", "w.take(received_[receivedNext_++], false, -1);",
     "a batch's later rays lose the link they came on: passed between columns goes uncounted for them"),
    ("every-forward-counted-as-passed", "models/node/node.cpp",
     "const bool passing = dir >= 0;", "const bool passing = true;",
     "every ray forwarded counts as passed on untraced, also the ones traced here first"),
    ("spare-list-over-a-started-batch", "models/channel/ray_batcher.h",
     "if (batch.capacity() == 0 && !spare_.empty()) {",
     "if (batch.capacity() <= 1 && !spare_.empty()) {",
     "a batch whose first ray has a list of its own size is replaced by a spare list: that ray is lost"),
    ("frame-buffer-unit-pixel-offset", "models/framebuffer/frame_buffer.cpp",
     "img.pixels[p] = units[p % n].pixel(p);", "img.pixels[p] = units[(p + 1) % n].pixel(p);",
     "the image takes each pixel's sum from the next unit's sums"),
    ("late-unit-takes-at-kernel-time", "models/framebuffer/frame_buffer.cpp",
     "if (late_ == 0) now_ = sc_core::sc_time_stamp().value();", "now_ = sc_core::sc_time_stamp().value();",
     "a frame-buffer unit taking its input late takes it at the kernel's time, not its own"),
    ("late-unit-stays-late", "models/framebuffer/frame_buffer.cpp",
     "if (late_ > 0) inputOrder_.setLate(0, ~size_t(0));", "(void)0;",
     "a late frame-buffer unit stays late after fb_expect, so its fb_done may leave behind the kernel"),
    ("pixel-sum-rounds-half-down", "sw/pixel_sum.cpp",
     "if (frac >= 0.5) ++i;", "if (frac >= 0.75) ++i;",
     "the pixel sum rounds a contribution down from half to three quarters of its unit"),
    ("pixel-sum-wraps-past-64-bits", "sw/pixel_sum.cpp",
     "if (fits && !__builtin_add_overflow(narrow, int64_t(v.c[a]), &sum)) narrow = sum;",
     "if (fits) { __builtin_add_overflow(narrow, int64_t(v.c[a]), &sum); narrow = sum; }",
     "a pixel's 64-bit sum wraps around instead of going on in 128 bits"),
    ("lookahead-counts-on-a-ray", "models/channel/link.h",
     "Picos lookahead() const { return linkLookahead(params_, smallest_); }",
     "Picos lookahead() const { return linkLookahead(params_, kHeaderBytes + kRayBytes); }",
     "a process's lookahead counts on a ray message's wire time, also where acks and headers alone travel"),
    ("blocked-queue-ahead-of-the-kernel", "models/node/node.cpp",
     "if (now_ > sc_core::sc_time_stamp().value() && !time_.mayIdleUntil(now_)) {",
     "if (false) {",
     "a node that blocks records its queue at a time beyond its lookahead, missing messages not yet sent"),
    ("run-ahead-takes-unseen-order", "models/node/node.cpp",
     "if (runAhead_ && !time_.sees(best >= 0 ? next : now_)) {",
     "if (runAhead_ && best < 0 && !time_.sees(now_)) {",
     "a node running ahead takes the oldest message it has, though one still to be sent may arrive before it"),
    ("sees-the-lookahead-instant", "models/process/time_keeper.h",
     "bool sees(Picos t) const { return t < kernel() + quantum_; }",
     "bool sees(Picos t) const { return t <= kernel() + quantum_; }",
     "a process running ahead counts as seen the instant a message sent at the kernel's time may still arrive"),
    ("counts-mode-skips-the-take-time", "models/channel/link.cpp",
     "    l.takenAt_[j] = t;\n", "    if (distributions_) l.takenAt_[j] = t;\n",
     "with --link-stats counts a link forgets when its messages were taken, so their slots come back at stale times"),
    ("lookahead-too-long-at-zero-latency", "models/channel/link_params.h",
     "{ return p.latency + wireTime(p, smallest); }",
     "{ return p.latency + wireTime(p, smallest) + (p.latency == 0 ? 50000 : 0); }",
     "a link with no latency lets its receiver run 50 ns further ahead than its smallest message's time on the wire"),
    ("ledger-counts-the-whole-step-past-the-end", "models/node/time_ledger.cpp",
     "t_.busy = prev.busy + (running ? end - stepStart : 0);",
     "t_.busy = prev.busy + (running ? c.busy - prev.busy : 0);",
     "a node running ahead under a dynamic policy counts the whole step it was in at the frame's end as busy"),
    ("run-ahead-depth-forgets-taken", "models/base/queue_marks.h",
     "size_t(d.own + takenSince + in.arrivedBy(d.t))", "size_t(d.own + in.arrivedBy(d.t))",
     "a queue depth settled late leaves out the messages taken since"),
]


def run(cmd, cwd, log, env=None):
    """Runs cmd, its output appended to the log; its exit code. The build or
    suite runs in a process group of its own, killed whole if this script is
    stopped (Ctrl-C, SIGTERM: outputs.guard), so that no ctest outlives it."""
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        p = subprocess.Popen(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        try:
            return p.wait()
        except BaseException:
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait()
            raise


def failed_tests(junit):
    """Names of the tests that did not pass, from ctest's JUnit output."""
    if not os.path.exists(junit):
        return ["(no test results)"]
    out = []
    for case in ET.parse(junit).getroot().iter("testcase"):
        if case.get("status") not in (None, "run") or case.find("failure") is not None:
            out.append(case.get("name"))
    return out


def stale(mutants):
    """The mutants whose text to change is not in their file exactly once."""
    out = []
    for name, path, old, _, _ in mutants:
        with open(os.path.join(ROOT, path)) as f:
            n = f.read().count(old)
        if n != 1:
            out.append(f"{name} ({path}: {n} times)")
    return out


MARK = ".rtsim-mutate"  # the file that says a work directory is this script's


def own_work_dir(work):
    """The work directory, made or taken if it is this script's own (empty,
    or holding MARK; a folder of an older mutate.py, without it, is refused
    too: its files cannot be told from anyone's): its src/ is removed at every run, so a folder of
    anyone else's is refused. Not in the repository's tree, but under out/
    (git status stays clean)."""
    work = os.path.abspath(work)
    if outputs.under(work, ROOT) and not outputs.under(work, outputs.OUT):
        raise outputs.ToolError(f"--work {work}: in the repository; a folder elsewhere, or under out/")
    if os.path.lexists(work) and not os.path.isdir(work) or os.path.islink(work):
        raise outputs.ToolError(f"--work {work}: not a folder")
    if os.path.isdir(work) and os.listdir(work) and not os.path.isfile(os.path.join(work, MARK)):
        raise outputs.ToolError(f"--work {work}: a folder that is not mutate.py's (no {MARK} in it); "
                                "name a new or empty one")
    try:
        os.makedirs(work, exist_ok=True)
        open(os.path.join(work, MARK), "a").close()
    except OSError as e:
        raise outputs.ToolError(f"--work {work}: {e.strerror}")
    return work


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", default="/tmp/rtsim-mutate", help="work directory (sources, build, logs)")
    ap.add_argument("--only", default="", help="comma-separated mutant names")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--doc", action="store_true",
                    help="write the table to doc/results/mutate.md and doc/robustness.md (without it: "
                         "out/results/mutate.md; with --only: the work directory)")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--check", action="store_true",
                    help="only check that every mutant's text is in its file exactly once (the suite runs this, "
                         "so a change to models/ that a planted bug no longer fits fails there, not an hour into a run)")
    args = ap.parse_args()
    if args.list:
        for name, path, _, _, what in MUTANTS:
            print(f"{name:30s} {path:28s} {what}")
        return 0
    chosen = [m for m in MUTANTS if not args.only or m[0] in args.only.split(",")]
    unknown = set(filter(None, args.only.split(","))) - {m[0] for m in MUTANTS}
    if unknown:
        print(f"mutate.py: unknown mutant(s): {', '.join(sorted(unknown))}", file=sys.stderr)
        return 2
    if args.only and args.doc:
        print("mutate.py: --doc publishes the whole table; it cannot go with --only", file=sys.stderr)
        return 2
    if args.jobs < 1:
        raise outputs.ToolError(f"--jobs {args.jobs}: at least 1")

    # Every mutant's text must sit exactly once in its file before anything is
    # built: a text that drifted from the code would otherwise stop the run
    # midway, after an hour of building.
    drifted = stale(MUTANTS if args.check else chosen)
    if drifted:
        print(f"mutate.py: the text to change is not found exactly once for: {'; '.join(drifted)}", file=sys.stderr)
        return 2
    if args.check:
        print(f"mutate.py: all {len(MUTANTS)} mutants' texts found once each")
        return 0

    args.work = own_work_dir(args.work)
    # Where the table goes, checked now rather than after an hour of builds.
    # A partial run (--only) leaves the published table alone: its table goes
    # to the work directory; a whole one to out/results/, or with --doc to
    # doc/results/.
    results = args.work if args.only else RESULTS if args.doc else os.path.dirname(outputs.out_path("results", "x"))
    outputs.check_output(os.path.join(results, "mutate.md"), "the table", doc=args.doc)
    if args.doc:
        outputs.check_output(os.path.join(ROOT, "doc", "robustness.md"), "--doc", doc=True)
    src, log = (os.path.join(args.work, d) for d in ("src", "log.txt"))
    build = os.path.join(src, "build")  # where the scripts the suite runs look for rtsim, as in a clone
    if os.path.exists(src):
        shutil.rmtree(src)
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True).stdout.split(b"\0")
    for f in filter(None, files):
        rel = f.decode()
        os.makedirs(os.path.dirname(os.path.join(src, rel)) or src, exist_ok=True)
        shutil.copy(os.path.join(ROOT, rel), os.path.join(src, rel))  # new times: make rebuilds all
    # A repository of its own, so the build and the sweeps see a version.
    git = ["git", "-c", "user.name=mutate", "-c", "user.email=mutate@localhost"]
    for cmd in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "mutate.py: the sources under test"]):
        subprocess.run(git + cmd, cwd=src, check=True, capture_output=True)
    open(log, "w").close()
    # The sources find the scenes beside them (../shared), as in a clone.
    shared = os.path.join(args.work, "shared")
    if not os.path.exists(shared):
        os.symlink(os.path.realpath(os.path.join(ROOT, "..", "shared")), shared)
    if run(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release"], src, log):
        print(f"mutate.py: cmake failed (see {log})", file=sys.stderr)
        return 1

    def suite():
        """Builds and runs the suite; the failing tests (None: did not build)."""
        if run(["cmake", "--build", build, "-j", str(args.jobs)], src, log):
            return None
        junit = os.path.join(args.work, "junit.xml")
        if os.path.exists(junit):
            os.remove(junit)
        # The tests' temporary folders in one of the run's own, emptied after
        # every suite: a test that a mutant makes hang is killed at the
        # timeout, before its TearDown removes its folder.
        tmp = os.path.join(args.work, "tmp")
        shutil.rmtree(tmp, ignore_errors=True)
        os.makedirs(tmp)
        # (Not MutantsApply: a planted mutant is, by design, text that no longer fits.)
        run(["ctest", "-j", str(args.jobs), "--timeout", "120", "-E", "^MutantsApply$", "--output-junit", junit], build, log,
            env=dict(os.environ, TMPDIR=tmp))
        shutil.rmtree(tmp, ignore_errors=True)
        return failed_tests(junit)

    t0 = time.time()
    base = suite()
    if base is None or base:
        print(f"mutate.py: the unmutated suite does not pass ({base}); see {log}", file=sys.stderr)
        return 1
    rows, missed = [], []
    for name, path, old, new, what in chosen:
        p = os.path.join(src, path)
        with open(p) as f:
            text = f.read()
        if text.count(old) != 1:
            print(f"mutate.py: {name}: the text to change occurs {text.count(old)} times in {path}", file=sys.stderr)
            return 1
        with open(p, "w") as f:
            f.write(text.replace(old, new))
        try:
            failed = suite()
        finally:
            with open(p, "w") as f:
                f.write(text)
        if failed is None:
            verdict, detail = "did not build", ""
            missed.append(name)
        elif failed:
            verdict = f"caught by {len(failed)}"
            detail = ", ".join(sorted(failed)[:3]) + (", ..." if len(failed) > 3 else "")
        else:
            verdict, detail = "**missed**", ""
            missed.append(name)
        others = [t for t in failed or [] if not any(o in t for o in ORACLES)]
        without = f"{len(others)}" if others else "**0: missed**"
        print(f"{name}: {verdict}; without the oracles {len(others)}; {detail}", flush=True)
        rows.append(f"| `{name}` | {what} | {verdict} | {without} | {detail} |")
    suite()  # leave the work build unmutated
    lines = [
        "<!-- written by scripts/mutate.py -->",
        f"{len(chosen) - len(missed)} of {len(chosen)} planted timing bugs caught by the suite "
        f"({(time.time() - t0) / 60:.0f} minutes on {args.jobs} jobs).",
        "",
        "| mutant | the planted bug | tests failing | of them not timing oracles | some of them |",
        "|---|---|---|---|---|",
    ] + rows
    publish_table(lines, os.path.join(results, "mutate.md"),
                  os.path.join(ROOT, "doc", "robustness.md") if args.doc else None, "mutate")
    if args.only:
        print(f"mutate.py: --only: table in {os.path.join(results, 'mutate.md')}, doc/results left alone", file=sys.stderr)
    elif not args.doc:
        print(f"mutate.py: table in {os.path.join(results, 'mutate.md')}; --doc publishes it", file=sys.stderr)
    if missed:
        print(f"mutate.py: missed: {', '.join(missed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(outputs.guard("mutate.py", main))
