#include "node/fb_outbox.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rt {

void FrameBufferOutbox::send(int unit, Outbox& out) {
    std::vector<Contribution>& p = pending_[size_t(unit)];
    std::vector<Contribution> batch;
    if (p.size() >= size_t(batch_)) {  // a full batch: hand over the list itself
        batch.swap(p);
        p.reserve(size_t(batch_));     // the unit keeps the list: it should hold no spare room
    } else {
        batch.assign(p.begin(), p.end());  // a part batch: a list of its size
        p.clear();
    }
    count_ -= batch.size();
    sentSince_[size_t(unit)] += uint32_t(batch.size());
    sentAny_ = true;
    out.push_back({target(unit), Message::contributions(std::move(batch))});
}

bool FrameBufferOutbox::flushAll(Outbox& out) {
    // (count_ and sentAny_ spare a flush with nothing pending or sent the
    // scans of every unit's list and count: a node flushes before each wait.)
    if (count_ > 0)
        for (size_t u = 0; u < pending_.size(); ++u)
            if (!pending_[u].empty()) send(int(u), out);
    if (holdsCredit()) {
        std::vector<std::pair<uint16_t, uint32_t>> counts;
        if (sentAny_) {
            for (size_t u = 1; u < sentSince_.size(); ++u)
                if (sentSince_[u]) counts.push_back({uint16_t(u), sentSince_[u]});
            std::fill(sentSince_.begin(), sentSince_.end(), 0);
            sentAny_ = false;
        }
        credit_.add(sampleCredit_);  // (the message carries the whole, and the sample's part again)
        out.push_back({target(0), Message::credit(credit_, std::move(counts), sampleCredit_)});
        credit_.clear();
        sampleCredit_.clear();
        holds_ = holdsSample_ = false;
    } else if (sentAny_) {
        return false;  // a contribution is made with credit kept for it (Node::terminate), so this cannot happen
    }
    return true;
}

}  // namespace rt
