#pragma once
// The functional state of one renderer's PP array: every PP's local-memory fields, its enable bit and
// its backing store, and the execution of a PpProgram over all PPs at once. Values are exact
// integers at the fields' widths, as the bit-serial hardware would compute them; execution is host
// vector code, the whole program over one block of PPs after another, one instruction at a time across
// the block (never bit by bit).
//
// Every write is masked by the enable bit, as on the hardware: a PP that is disabled keeps its old
// field values.

#include "sim/pixel_processors/pp_backing_window.h"
#include "sim/pixel_processors/pp_field_store.h"
#include "sim/pixel_processors/pp_program.h"

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace pp5 {

struct PpNarrowPlan;

// Fixed-point coefficients of one quadratic expression, as the controller feeds them to the QEE.
struct QeeCoefficients {
    std::int64_t a = 0, b = 0, c = 0, d = 0, e = 0, f = 0;  // A x^2 + B x y + C y^2 + D x + E y + F
};

// What changes from one run of a program to the next: the voxel slot and the QEE expressions.
struct PpSlotContext {
    int record_base_bit = 0;                       // the slot's record in each PP's backing store
    std::span<const QeeCoefficients> expressions;  // at least program.expressions of them
};

// Work counts of one run: integers, the same at any thread count.
struct PpRunCounts {
    std::uint64_t instructions = 0;
    std::uint64_t pp_operations = 0;          // instructions x PPs
    std::uint64_t enabled_pp_operations = 0;  // of them, on enabled PPs

    PpRunCounts& operator+=(const PpRunCounts& other);
};

class PpArray {
public:
    // Throws std::invalid_argument for a non-positive size.
    PpArray(int columns, int rows, int local_memory_bits, int backing_store_bits);

    int columns() const { return columns_; }
    int rows() const { return rows_; }
    int size() const { return columns_ * rows_; }  // PPs; PP p sits at column p % columns, row p / columns
    int local_memory_bits() const { return local_memory_bits_; }
    int backing_store_bits() const { return backing_store_bits_; }

    // Backing-store access from outside the array (data arriving over the ring, results read back).
    // Throws std::out_of_range past the store's end; bits in 1..64.
    void write_backing(int pp, int bit_offset, int bits, std::uint64_t value);
    std::uint64_t read_backing(int pp, int bit_offset, int bits) const;
    // The same bits of every PP, checked once, for reading or writing PP after PP. Throws
    // std::out_of_range past the store's end; bits in 1..64.
    PpBackingReader backing_reader(int bit_offset, int bits) const;
    PpBackingWriter backing_writer(int bit_offset, int bits);

    // Runs the program once over every PP (the enable bit starts set on every PP). Throws
    // std::invalid_argument if the program needs more local memory than the array has, more QEE
    // expressions than the context gives, or a record past the backing store's end.
    PpRunCounts run(const PpProgram& program, const PpSlotContext& context);
    // The same run, computed on the host for `candidates` only (distinct PPs, ascending): every other PP
    // must be a bystander of the program (pp_program.h), one its first test after each EnableAll rules
    // out, which the caller vouches for (a kernel tells them from its QEE expressions; its tests
    // compare with run() bit for bit). Bystanders keep their backing store and are counted as the
    // hardware runs them, so the counts equal run()'s. Fields afterwards hold the candidates' values, in
    // list order. Throws std::invalid_argument as run() does, for a candidate list out of order or
    // range, and for a program whose bystanders would store.
    PpRunCounts run_candidates(const PpProgram& program, const PpSlotContext& context, std::span<const int> candidates);

    // Whether the last run used 32-bit lanes (for tests and inspection).
    bool ran_in_narrow_lanes() const { return narrow_current_; }
    // A field's value in every PP after the last run (for tests and inspection).
    std::vector<std::int64_t> field_values(const PpField& field) const;

private:
    void check_backing_range(int bit_offset, int bits) const;
    // Runs a validated program over every PP (Listed = false) or over `listed` PPs, each field's values
    // held in lanes of type Lane (32 bits when every field fits them, else 64); `zero_extended` marks
    // the 32-bit unsigned fields of a run in 32-bit lanes.
    template <class Lane, bool Listed>
    PpRunCounts execute(const PpProgram& program, const PpSlotContext& context, std::span<const int> listed,
                        std::span<const std::uint8_t> zero_extended);
    // The plan to run a program in 32-bit lanes when it can (its fields fit them, and so does every
    // value the fields hold now: fields carry state from one program to the next, as local memory
    // does), else null. Moves the values into the storage of the lanes chosen.
    const PpNarrowPlan* choose_narrow_lanes(const std::optional<PpNarrowPlan>& plan);
    template <class Lane>
    PpFieldStore<Lane>& field_storage() {
        if constexpr (sizeof(Lane) == sizeof(std::int32_t)) return narrow_fields_;
        else return wide_fields_;
    }

    int columns_;
    int rows_;
    int local_memory_bits_;
    int backing_store_bits_;
    int backing_words_;  // 64-bit words per PP
    // Word-major: word w of PP p at [w * size() + p], so the words of the slots a kernel never uses lie
    // together at the end. calloc gives a large block as fresh zero pages that take host memory only
    // once written: the machine's whole backing store is declared, what a volume fills is resident.
    struct FreeStore {
        void operator()(std::uint64_t* words) const { std::free(words); }
    };
    std::unique_ptr<std::uint64_t[], FreeStore> backing_;
    // By storage slot (PpField::storage), one value per PP: in 32-bit lanes or 64-bit ones, whichever
    // the last run used (narrow_current_).
    PpFieldStore<std::int32_t> narrow_fields_;
    PpFieldStore<std::int64_t> wide_fields_;
    bool narrow_current_ = true;
    std::vector<std::uint8_t> zero_extended_slots_;  // by slot, in 32-bit lanes: holds a 32-bit unsigned field
    std::vector<std::uint8_t> enabled_;
};

}  // namespace pp5
