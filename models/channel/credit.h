// Exact credit for end-of-frame detection by weight throwing (Mattern 1989;
// Huang 1989). The host starts with credit 1 and hands parts of it to the
// nodes; every ray carries a credit 2^-e; a ray that spawns children splits
// its credit among them; a ray that ends gives its credit back to its node,
// which returns what it holds to the host whenever it goes idle. The host
// knows the frame is done when the credit it got back sums to exactly 1.
// Credits are dyadic fractions kept as fixed-point words, so the sum is exact.
#pragma once
#include <cstdint>
#include <vector>

namespace rt {

class Credit {
public:
    // No credit, and no room for any: what a message that carries none holds
    // (so creating a message allocates nothing for it).
    Credit() = default;
    // A credit able to hold fractions down to 2^-maxExponent.
    explicit Credit(int maxExponent) : words_(1 + (maxExponent + 63) / 64, 0) {}
    static Credit one(int maxExponent) {
        Credit c(maxExponent);
        c.words_[0] = 1;
        return c;
    }
    // Adds k * 2^-e.
    void add(int e, uint64_t k = 1);
    void add(const Credit& o);
    bool isZero() const;
    bool isOne() const;
    bool operator==(const Credit& o) const { return words_ == o.words_; }
    void clear() { std::fill(words_.begin(), words_.end(), 0); }
    // Bytes a message carrying it needs: the words up to the last nonzero one.
    uint32_t bytes() const;
    double value() const;  // for progress display only

private:
    std::vector<uint64_t> words_;  // [0]: whole part; [i]: bits 2^-(64(i-1)+1) .. 2^-(64 i)
};

// Smallest c with 2^c >= n (n >= 1).
int ceilLog2(uint64_t n);

}  // namespace rt
