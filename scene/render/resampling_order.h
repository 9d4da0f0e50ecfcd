#pragma once
// Where classification and shading happen relative to resampling: a choice every kernel shares.

namespace pp5 {

enum class ResamplingOrder {
    ShadeThenInterpolate,  // Levoy: classify and shade the voxels, interpolate colours and opacities
    InterpolateThenShade,  // interpolate value and gradient, classify and shade each sample
};

}  // namespace pp5
