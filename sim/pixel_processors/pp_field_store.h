#pragma once
// Where the host keeps the PPs' fields while programs run: for each storage slot (PpField::storage), an
// array with one lane per PP.
//
// The arrays share one block, each starting at its own offset within a 4 KB page. An instruction's loop
// reads one field's array and writes another's, lane after lane; were the two a multiple of 4 KB apart
// (nearly so, as separate heap arrays of 64 KB or more tend to be), each load would look to an x86 core
// like one of the stores just before it ("4K aliasing") and wait for it. Staggering the arrays took a
// 256^3 shading pass from 166-167 ms to 156-160 ms.

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <span>

namespace pp5 {

template <class Lane>
class PpFieldStore {
public:
    explicit PpFieldStore(std::size_t lanes) : lanes_(lanes) {
        // Whole pages per array, plus a skew of 17 cache lines: slot k starts 17 k lines into a page
        // (modulo 64 lines), and 17 is prime to 64, so 64 slots in a row start on 64 different lines.
        constexpr std::size_t kPage = 4096;
        constexpr std::size_t kSkew = 17 * 64;
        stride_ = ((lanes * sizeof(Lane) + kPage - 1) / kPage * kPage + kSkew) / sizeof(Lane);
    }

    std::size_t slots() const { return slots_; }
    std::size_t lanes() const { return lanes_; }

    // At least `slots` arrays: those there keep their values, new ones hold 0.
    void reserve(std::size_t slots) {
        if (slots <= slots_) return;
        const std::size_t bytes = (slots * stride_ * sizeof(Lane) + kAlign - 1) / kAlign * kAlign;
        Block grown(static_cast<Lane*>(std::aligned_alloc(kAlign, bytes)));
        if (!grown) throw std::bad_alloc();
        std::fill_n(grown.get(), bytes / sizeof(Lane), Lane{0});
        for (std::size_t s = 0; s < slots_; ++s) std::copy_n(slot(s), lanes_, grown.get() + s * stride_);
        block_ = std::move(grown);
        slots_ = slots;
    }

    // Each slot's values made from `from`'s by convert(slot, value); slots `from` lacks hold 0, as new
    // ones do.
    template <class From, class Convert>
    void assign_converted(const PpFieldStore<From>& from, Convert convert) {
        reserve(from.slots());
        for (std::size_t s = 0; s < slots_; ++s) {
            Lane* to = slot(s);
            if (s >= from.slots()) {
                std::fill_n(to, lanes_, Lane{0});
                continue;
            }
            const From* values = from.slot(s);
            for (std::size_t i = 0; i < lanes_; ++i) to[i] = convert(s, values[i]);
        }
    }

    Lane* slot(std::size_t s) { return block_.get() + s * stride_; }
    const Lane* slot(std::size_t s) const { return block_.get() + s * stride_; }
    std::span<Lane> values(std::size_t s) { return {slot(s), lanes_}; }
    std::span<const Lane> values(std::size_t s) const { return {slot(s), lanes_}; }

private:
    static constexpr std::size_t kAlign = 4096;
    struct Free {
        void operator()(Lane* lanes) const { std::free(lanes); }
    };
    using Block = std::unique_ptr<Lane[], Free>;

    std::size_t lanes_;
    std::size_t stride_;  // lanes from one array's start to the next
    std::size_t slots_ = 0;
    Block block_;
};

}  // namespace pp5
