// Modules a machine owns by the tens of thousands (its nodes): as an
// sc_vector holds them, but taken down in an order SystemC finds fast.
//
// Why not sc_vector: SystemC takes a module out of its registry, and out of
// its parent's children, by a search from the front of each list, and a
// port out of its registry by a search from the back; each then moves the
// last entry into the hole. sc_vector deletes its elements last first, so
// each deletion searched the module lists to their end: at 32,768 nodes,
// two searches of 32,768 entries per node (doc/history.md, "At 32x32x32").
// Here the modules' ports go first, newest first, each found at the back
// of its registry (T::releasePorts). Then the first kLead modules, first
// first: each is found near the front, and the entries made after ours (the
// kernel's own module, made when the simulation starts, and any of the
// machine's) move into their places, ahead of ours. Then the rest, last
// first: each in turn has been moved to the front by the one before.
#pragma once
#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include <systemc>

namespace rt {

template <class T>
class ModuleArray {
    using Owned = std::vector<std::unique_ptr<T>>;

    // An iterator that reads as T&, as sc_vector's does.
    template <class It, class Ref>
    class Iter {
    public:
        explicit Iter(It it) : it_(it) {}
        Ref operator*() const { return **it_; }
        Iter& operator++() {
            ++it_;
            return *this;
        }
        bool operator!=(const Iter& o) const { return it_ != o.it_; }

    private:
        It it_;
    };

public:
    ModuleArray() = default;
    ModuleArray(const ModuleArray&) = delete;
    ModuleArray& operator=(const ModuleArray&) = delete;
    ~ModuleArray() { clear(); }

    // n modules, the i-th made by make(i) (a new T, named by its maker,
    // child of the module being built).
    template <class Make>
    void init(size_t n, Make make) {
        items_.reserve(n);
        for (size_t i = 0; i < n; ++i) items_.emplace_back(make(i));
    }
    size_t size() const { return items_.size(); }
    T& operator[](size_t i) { return *items_[i]; }
    const T& operator[](size_t i) const { return *items_[i]; }
    auto begin() { return Iter<typename Owned::iterator, T&>(items_.begin()); }
    auto end() { return Iter<typename Owned::iterator, T&>(items_.end()); }
    auto begin() const { return Iter<typename Owned::const_iterator, const T&>(items_.begin()); }
    auto end() const { return Iter<typename Owned::const_iterator, const T&>(items_.end()); }

    // Deletes them: their ports newest first, then the first kLead
    // modules first first, then the rest last first (above).
    void clear() {
        for (size_t i = items_.size(); i-- > 0;) items_[i]->releasePorts();
        const size_t lead = std::min(kLead, items_.size());
        for (size_t i = 0; i < lead; ++i) items_[i].reset();
        for (size_t i = items_.size(); i-- > lead;) items_[i].reset();
        items_.clear();
    }

private:
    // More than the entries that follow ours in SystemC's lists as they are
    // taken down (the kernel's module, the express relay).
    static constexpr size_t kLead = 8;
    Owned items_;
};

}  // namespace rt
