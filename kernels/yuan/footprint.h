#pragma once
// The reconstruction kernel and its footprint: a spherical Gaussian of standard deviation sigma cut
// off at radius r (voxel units), integrated along parallel rays and normalised to unit area, so that
// the footprints of a lattice of voxels sum to nearly one (0.978 to 1.000 for sigma = 0.7, r = 2) and a
// layer of voxels of opacity alpha covers the screen with about alpha.
//
// The renderers look the weight up in a table over the squared index i^2 (2^table_bits entries, in
// accumulator units). Under perspective each row of the table belongs to one cone angle: the row maps
// Yuan's affine index to the true distance of the pixel's ray from the kernel's centre
// (corrected_index_squared), so the correction costs the renderers nothing per pixel.

#include "sim/pixel_processors/pp_program.h"

#include <map>
#include <mutex>

namespace pp5 {

class GaussianFootprint {
public:
    GaussianFootprint(double sigma, double radius);
    // The integrated kernel at distance rho (voxels) from its centre line, per voxel^2 of screen.
    double operator()(double rho) const;
    double radius() const { return radius_; }

private:
    double sigma_;
    double radius_;
    double norm_;
};

class FootprintTables {
public:
    // `alpha_step`: radians between rows; `corrected`: rows hold Yuan's corrected index (else every row is
    // the plain table, for the exact index or a parallel camera).
    FootprintTables(const GaussianFootprint& kernel, int table_bits, int accumulator_bits, double alpha_step,
                    bool corrected);
    // The row for a splat of half cone angle `alpha` (radians): its number and its table.
    int row_of(double alpha) const;
    const PpTable& table(int row) const;  // made when first asked for (thread-safe)
    int table_bits() const { return table_bits_; }

private:
    PpTable build(int row) const;

    GaussianFootprint kernel_;
    int table_bits_;
    int accumulator_bits_;
    double alpha_step_;
    bool corrected_;
    mutable std::mutex mutex_;
    mutable std::map<int, PpTable> rows_;
};

}  // namespace pp5
