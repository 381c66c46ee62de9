// A first-in first-out queue that allocates nothing until its first push:
// a vector and the index of its front. A link holds five of them, and a
// machine with a frame-buffer port from every node to every unit has tens of
// thousands of links, most of them idle most of the time; std::deque
// allocates about 600 bytes each before it holds anything.
#pragma once
#include <cstddef>
#include <utility>
#include <vector>

namespace rt {

template <class T>
class Fifo {
public:
    bool empty() const { return head_ == items_.size(); }
    size_t size() const { return items_.size() - head_; }
    T& front() { return items_[head_]; }
    const T& front() const { return items_[head_]; }
    const T& operator[](size_t i) const { return items_[head_ + i]; }
    T& operator[](size_t i) { return items_[head_ + i]; }
    void push_back(T v) { items_.push_back(std::move(v)); }
    void pop_front() {
        items_[head_] = T();  // let go of what it holds now
        if (++head_ == items_.size()) {  // empty: keep a little room, give back a burst's
            if (items_.capacity() > kKeep) std::vector<T>().swap(items_);
            else items_.clear();
            head_ = 0;
        } else if (head_ >= kKeep && 2 * head_ >= items_.size()) {  // compact: the front half is spent
            items_.erase(items_.begin(), items_.begin() + std::ptrdiff_t(head_));
            head_ = 0;
            if (items_.capacity() > 4 * items_.size() + kKeep) items_.shrink_to_fit();
        }
    }

private:
    static constexpr size_t kKeep = 32;
    std::vector<T> items_;
    size_t head_ = 0;
};

}  // namespace rt
