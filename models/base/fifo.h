// A first-in first-out queue that allocates nothing until its first push. A
// link holds several, and a machine with a frame-buffer port from every node
// to every unit has tens of thousands of links, most of them idle most of
// the time (std::deque allocates about 600 bytes each before it holds
// anything).
//
// Up to one chunk's worth of items (about 64 KiB) it is a ring buffer whose
// capacity doubles as it fills: a ring moves nothing when it pops and reads
// its items in address order, which the processor prefetches. Past that it
// is a list of such chunks, filled at the back and freed at the front, so a
// backlog of 100,000 messages that the receiver takes long after they were
// sent is never copied to a block twice its size (each doubling touches
// fresh pages, which the kernel zeroes) and holds at most three chunks more
// than its items need. A ring keeps its room: with a quantum most links
// fill and drain every quantum, and giving the room back when the ring
// drained or ran empty (then doubling it again from a few items at the next
// burst) would move each message about once more. So a ring holds room for
// the largest burst it has had, at most a chunk (64 KiB); a queue of chunks
// gives them all back when it runs empty. (What each choice bought:
// doc/history.md, "Figures behind the code's comments".)
#pragma once
#include <cstddef>
#include <cstdint>
#include <deque>
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
        clear();  // (an empty queue is a ring, or nothing)
        ::operator delete(mem_);
    }

    bool empty() const { return size_ == 0; }
    size_t size() const { return size_; }
    T& front() { return cap_ ? ring()[head_] : chunks()->list.front()[head_]; }
    const T& front() const { return const_cast<Fifo*>(this)->front(); }
    T& operator[](size_t i) { return cap_ ? ring()[(head_ + i) & (cap_ - 1)] : chunkSlot(i); }
    const T& operator[](size_t i) const { return (*const_cast<Fifo*>(this))[i]; }

    void push_back(T v) { emplace_back(std::move(v)); }
    // Builds the item in place (braces: an aggregate takes its fields), so
    // a large item is not moved once more on its way in. A ring with room
    // takes it at once; growing, and the chunks, are the slow path.
    template <class... Args>
    void emplace_back(Args&&... args) {
        T* at = size_ < cap_ ? &ring()[(head_ + size_) & (cap_ - 1)] : backSlot();
        new (at) T{std::forward<Args>(args)...};
        ++size_;
    }
    void pop_front() {
        if (cap_ && size_ > 1) {  // a ring that does not run empty
            ring()[head_].~T();
            head_ = (head_ + 1) & (cap_ - 1);
            --size_;
            return;
        }
        popSlow();
    }
    void clear() {
        while (size_) pop_front();
    }

    // Items per chunk: a power of two, about 64 KiB of them.
    static constexpr size_t kChunk = [] {
        size_t n = 8;
        while (2 * n * sizeof(T) <= 65536) n *= 2;
        return n;
    }();

private:
    // Chunk mode's state, allocated only in it (a std::deque allocates when
    // made, and an idle link has a dozen queues).
    struct Chunks {
        std::deque<T*> list;  // kChunk items each; the first item at head_ in the first
        T* spare = nullptr;   // the last chunk used up, for the next one
        ~Chunks() {
            for (T* c : list) ::operator delete(c);
            ::operator delete(spare);
        }
        T* take() {
            T* c = spare ? spare : static_cast<T*>(::operator new(kChunk * sizeof(T)));
            spare = nullptr;
            return c;
        }
        void keep(T* c) {
            ::operator delete(spare);
            spare = c;
        }
    };

    // Ring mode: cap_ > 0. Chunk mode: cap_ == 0 with mem_ set. Neither
    // (nothing allocated): both 0.
    bool chunked() const { return cap_ == 0 && mem_; }
    T* ring() const { return static_cast<T*>(mem_); }
    Chunks* chunks() const { return static_cast<Chunks*>(mem_); }
    T& chunkSlot(size_t i) const {
        const size_t pos = head_ + i;
        return chunks()->list[pos / kChunk][pos & (kChunk - 1)];
    }
    // Where the next item goes when the ring is full, or there is none, or
    // in chunk mode.
    T* backSlot() {
        if (!chunked()) {
            if (cap_ < kChunk) {
                resize(cap_ ? 2 * cap_ : 4);
                return &ring()[size_];  // (head_ is 0)
            }
            toChunks();
        }
        const size_t pos = head_ + size_;
        Chunks* c = chunks();
        if (pos == c->list.size() * kChunk) c->list.push_back(c->take());
        return &chunkSlot(size_);
    }
    void popSlow() {
        front().~T();
        --size_;
        if (chunked()) {
            if (++head_ == kChunk) {  // the first chunk is used up: kept for the next one at the back
                chunks()->keep(chunks()->list.front());
                chunks()->list.pop_front();
                head_ = 0;
            }
            if (size_ == 0) toRing();
            return;
        }
        head_ = (head_ + 1) & (cap_ - 1);
        if (size_ == 0) head_ = 0;  // (the ring keeps its room)
    }
    void resize(uint32_t cap) {
        T* to = static_cast<T*>(::operator new(cap * sizeof(T)));
        moveOut(to);
        ::operator delete(mem_);
        mem_ = to;
        cap_ = cap;
        head_ = 0;
    }
    // A full ring of one chunk's size: its items, in order, become the first chunk.
    void toChunks() {
        auto* c = new Chunks;
        c->list.push_back(c->take());
        moveOut(c->list.front());
        ::operator delete(mem_);
        mem_ = c;
        cap_ = 0;
        head_ = 0;
    }
    // Empty in chunk mode: back to no ring at all, every chunk given back.
    void toRing() {
        delete chunks();
        mem_ = nullptr;
        head_ = 0;
    }
    // Moves the ring's items, in order, to the front of `to`.
    void moveOut(T* to) {
        for (size_t i = 0; i < size_; ++i) {
            T& v = ring()[(head_ + i) & (cap_ - 1)];
            new (&to[i]) T(std::move(v));
            v.~T();
        }
    }
    void swap(Fifo& o) noexcept {
        std::swap(mem_, o.mem_);
        std::swap(cap_, o.cap_);
        std::swap(head_, o.head_);
        std::swap(size_, o.size_);
    }

    // The ring's items (ring mode) or the Chunks (chunk mode): one pointer
    // for both, so that a queue stays 24 bytes.
    void* mem_ = nullptr;
    uint32_t cap_ = 0;   // ring mode: its capacity (a power of two); 0 otherwise
    uint32_t head_ = 0;  // the first item's place in the ring, or in the first chunk
    size_t size_ = 0;
};

}  // namespace rt
