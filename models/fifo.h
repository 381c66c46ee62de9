// A first-in first-out queue that allocates nothing until its first push: a
// ring buffer whose capacity doubles as it fills. A link holds several, and a
// machine with a frame-buffer port from every node to every unit has tens of
// thousands of links, most of them idle most of the time (std::deque
// allocates about 600 bytes each before it holds anything). A ring moves
// nothing when it pops, and reads its items in address order, which the
// processor prefetches: a link's backlog can hold 100,000 messages that the
// receiver takes long after they were sent. A burst's memory is given back
// when the queue runs empty, and half of it when it is a quarter full, so a
// queue holds at most four times the room its items need (plus a little).
#pragma once
#include <cstddef>
#include <new>
#include <utility>

namespace rt {

template <class T>
class Fifo {
public:
    Fifo() = default;
    Fifo(const Fifo&) = delete;
    Fifo& operator=(const Fifo&) = delete;
    Fifo(Fifo&& o) noexcept { swap(o); }
    Fifo& operator=(Fifo&& o) noexcept {
        Fifo(std::move(o)).swap(*this);
        return *this;
    }
    ~Fifo() {
        clear();
        ::operator delete(items_);
    }

    bool empty() const { return size_ == 0; }
    size_t size() const { return size_; }
    T& front() { return items_[head_]; }
    const T& front() const { return items_[head_]; }
    T& operator[](size_t i) { return items_[(head_ + i) & mask_]; }
    const T& operator[](size_t i) const { return items_[(head_ + i) & mask_]; }

    void push_back(T v) { emplace_back(std::move(v)); }
    // Builds the item in place (braces: an aggregate takes its fields), so
    // a large item is not moved once more on its way in.
    template <class... Args>
    void emplace_back(Args&&... args) {
        if (size_ == capacity()) grow();
        new (&items_[(head_ + size_) & mask_]) T{std::forward<Args>(args)...};
        ++size_;
    }
    void pop_front() {
        items_[head_].~T();
        head_ = (head_ + 1) & mask_;
        if (--size_ == 0) {
            head_ = 0;
            if (capacity() > kKeep) release();  // empty: keep a little room, give back a burst's
        } else if (capacity() > kKeep && 4 * size_ <= capacity()) {
            resize(capacity() / 2);  // a quarter full: half the room (a backlog that shrinks but never empties)
        }
    }
    void clear() {
        while (size_) pop_front();
    }

private:
    static constexpr size_t kKeep = 32;
    size_t capacity() const { return items_ ? mask_ + 1 : 0; }
    void grow() { resize(capacity() ? 2 * capacity() : 4); }
    void resize(size_t cap) {
        T* items = static_cast<T*>(::operator new(cap * sizeof(T)));
        for (size_t i = 0; i < size_; ++i) {
            T& v = (*this)[i];
            new (&items[i]) T(std::move(v));
            v.~T();
        }
        ::operator delete(items_);
        items_ = items;
        mask_ = cap - 1;
        head_ = 0;
    }
    void release() {
        ::operator delete(items_);
        items_ = nullptr;
        mask_ = 0;
    }
    void swap(Fifo& o) noexcept {
        std::swap(items_, o.items_);
        std::swap(mask_, o.mask_);
        std::swap(head_, o.head_);
        std::swap(size_, o.size_);
    }

    T* items_ = nullptr;
    size_t mask_ = 0;  // capacity - 1 (a power of two)
    size_t head_ = 0;
    size_t size_ = 0;
};

}  // namespace rt
