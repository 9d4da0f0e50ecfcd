#pragma once
// Bit ranges of the PPs' backing store. The store is word-major (word w of PP p at store[w * pps + p]),
// so one range over all PPs is read in memory order, and a range may straddle two words.

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace pp5 {

// Where a bit range lies in each PP's words: the same for every PP.
struct PpBitWindow {
    int word;
    int shift;
    int bits;
    std::uint64_t mask;

    PpBitWindow(int offset, int width)
        : word(offset / 64), shift(offset % 64), bits(width), mask(width >= 64 ? ~0ull : (1ull << width) - 1) {}
    bool straddles() const { return shift + bits > 64; }
    std::uint64_t high_mask() const { return (1ull << (shift + bits - 64)) - 1; }

    std::uint64_t read(const std::uint64_t* store, std::size_t pps, std::size_t p) const {
        const std::uint64_t* low = store + static_cast<std::size_t>(word) * pps + p;
        std::uint64_t v = *low >> shift;
        if (straddles()) v |= low[pps] << (64 - shift);
        return v & mask;
    }
    void write(std::uint64_t* store, std::size_t pps, std::size_t p, std::uint64_t value) const {
        std::uint64_t* low = store + static_cast<std::size_t>(word) * pps + p;
        value &= mask;
        *low = (*low & ~(mask << shift)) | (value << shift);
        if (straddles()) low[pps] = (low[pps] & ~high_mask()) | (value >> (64 - shift));
    }
};

// The same bit range of every PP's backing store, its bounds checked once (PpArray::backing_reader and
// backing_writer) and then read or written PP after PP: what loading a volume and reading shaded codes
// back do for every voxel, without checking the range again each time.
template <class Word>
class PpBackingWindow {
public:
    // Throws std::out_of_range for a PP outside the array.
    std::uint64_t read(int pp) const { return window_.read(store_, pps_, index(pp)); }
    // out[i] = read(first + i) for each i of out: the PPs' range is checked once.
    void read_run(int first, std::span<std::uint64_t> out) const {
        if (out.empty()) return;
        index(first);
        index(first + static_cast<int>(out.size()) - 1);
        for (std::size_t i = 0; i < out.size(); ++i)
            out[i] = window_.read(store_, pps_, static_cast<std::size_t>(first) + i);
    }
    void write(int pp, std::uint64_t value) const requires(!std::is_const_v<Word>) {
        window_.write(store_, pps_, index(pp), value);
    }

private:
    friend class PpArray;
    PpBackingWindow(Word* store, std::size_t pps, int bit_offset, int bits)
        : store_(store), pps_(pps), window_(bit_offset, bits) {}
    std::size_t index(int pp) const {
        if (pp < 0 || static_cast<std::size_t>(pp) >= pps_)
            throw std::out_of_range("PP backing store: PP " + std::to_string(pp) + " of " + std::to_string(pps_));
        return static_cast<std::size_t>(pp);
    }

    Word* store_;
    std::size_t pps_;
    PpBitWindow window_;
};

using PpBackingReader = PpBackingWindow<const std::uint64_t>;
using PpBackingWriter = PpBackingWindow<std::uint64_t>;

}  // namespace pp5
