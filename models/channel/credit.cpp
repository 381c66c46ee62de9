#include "channel/credit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt {

int ceilLog2(uint64_t n) {
    int c = 0;
    while ((uint64_t(1) << c) < n) ++c;
    return c;
}

void Credit::add(int e, uint64_t k) {
    if (k == 0) return;
    if (e < 0 || words_.empty() || size_t(e) > 64 * (words_.size() - 1)) throw std::logic_error("credit exponent out of range");
    // 2^-e is bit (63 - (e - 1) % 64) of word (e + 63) / 64 (word 0 for e = 0).
    size_t w = e == 0 ? 0 : size_t((e + 63) / 64);
    const int bit = e == 0 ? 0 : 63 - (e - 1) % 64;
    // k * 2^bit may span two words.
    unsigned __int128 v = (unsigned __int128)k << bit;
    uint64_t lo = uint64_t(v), hi = uint64_t(v >> 64);
    for (;;) {
        const uint64_t before = words_[w];
        words_[w] += lo;
        uint64_t carry = (words_[w] < before) ? 1 : 0;
        carry += hi;
        if (carry == 0 || w == 0) break;
        lo = carry;
        hi = 0;
        --w;
    }
}

void Credit::add(const Credit& o) {
    if (o.words_.size() != words_.size()) throw std::logic_error("credit sizes differ");
    uint64_t carry = 0;
    for (size_t i = words_.size(); i-- > 0;) {
        const unsigned __int128 s = (unsigned __int128)words_[i] + o.words_[i] + carry;
        words_[i] = uint64_t(s);
        carry = uint64_t(s >> 64);
    }
}

bool Credit::isZero() const {
    return std::all_of(words_.begin(), words_.end(), [](uint64_t w) { return w == 0; });
}

bool Credit::isOne() const {
    return !words_.empty() && words_[0] == 1 && std::all_of(words_.begin() + 1, words_.end(), [](uint64_t w) { return w == 0; });
}

uint32_t Credit::bytes() const {
    size_t last = 0;
    for (size_t i = 0; i < words_.size(); ++i)
        if (words_[i]) last = i;
    return uint32_t(8 * (last + 1));
}

double Credit::value() const {
    double v = 0;
    for (size_t i = words_.size(); i-- > 0;) v = v / 18446744073709551616.0 + double(words_[i]);
    return v;
}

}  // namespace rt
