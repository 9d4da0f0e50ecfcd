#pragma once
// Viewing: a camera that turns a pixel into a ray in world space.
//
// World space is the volume's physical space: voxel (i,j,k) sits at (i,j,k) * spacing, in mm.
// Pixel (0,0) is the top-left of the image; rays pass through pixel centres. Pixels are square:
// the horizontal extent of the view follows from the vertical one and the image's aspect ratio.

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace pp5 {

enum class Projection { Parallel, Perspective };

struct Ray {
    glm::vec3 origin;
    glm::vec3 direction;  // unit length
};

struct Camera {
    Projection projection = Projection::Parallel;
    glm::vec3 eye{0.0f, 0.0f, -1.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fov_y_degrees = 30.0f;  // perspective: full vertical field of view
    float view_height = 1.0f;     // parallel: height of the visible window in world units (mm)

    glm::vec3 forward() const;  // unit vector from eye towards target
    // The ray through the centre of pixel (px, py) of a width x height image.
    // Parallel: the origin lies on the plane through the eye facing `forward`; perspective: the eye.
    Ray ray_for_pixel(int px, int py, int width, int height) const;

    bool operator==(const Camera&) const = default;
};

// Throws pp5::InputError (field "camera.*") for a camera that cannot form an image: eye == target,
// `up` parallel to the view direction, a field of view outside (0, 180) degrees, view_height <= 0,
// or non-finite numbers.
void validate_camera(const Camera& camera);

// The camera's orthonormal frame: right = forward x up, true_up = right x forward.
struct ViewBasis {
    glm::vec3 forward;
    glm::vec3 right;
    glm::vec3 up;
};
ViewBasis view_basis(const Camera& camera);

// The rays of one image, with the camera's frame worked out once rather than per pixel.
// ray(px, py) returns exactly what Camera::ray_for_pixel returns.
class PixelRays {
public:
    PixelRays(const Camera& camera, int width, int height);

    Ray ray(int px, int py) const {
        // Offsets of the pixel centre from the image centre, in pixels; y grows upwards in the view.
        const float dx = (static_cast<float>(px) + 0.5f - half_width_) * pixel_size_;
        const float dy = (half_height_ - (static_cast<float>(py) + 0.5f)) * pixel_size_;
        if (projection_ == Projection::Parallel) {
            return Ray{eye_ + dx * basis_.right + dy * basis_.up, basis_.forward};
        }
        return Ray{eye_, glm::normalize(basis_.forward + dx * basis_.right + dy * basis_.up)};
    }
    const ViewBasis& basis() const { return basis_; }

private:
    Projection projection_;
    glm::vec3 eye_;
    ViewBasis basis_;
    float half_width_;
    float half_height_;
    float pixel_size_;  // parallel: world units per pixel; perspective: per pixel at unit distance
};

// An orbit around an object: the eye on a sphere about `center`, looking at it, the object's bounding
// sphere (`radius`) just filling the height of the view at zoom 1.
//   azimuth 0, elevation 0: eye on the -y side, looking along +y, with +z up (for NIfTI heads in RAS
//   orientation, a view of the face). Azimuth turns the eye about +z, counter-clockwise seen from +z;
//   elevation raises it towards +z (+-90 looks straight down/up; `up` then follows the orbit).
struct OrbitView {
    float azimuth_degrees = 0.0f;
    float elevation_degrees = 0.0f;
    float distance_factor = 3.8637f;  // eye distance from the centre in radii; > 1. 1/sin(15 deg): VTK's framing
    float zoom = 1.0f;                // > 0; 2 shows the middle half of the bounding sphere's height
    Projection projection = Projection::Perspective;
};
// Throws pp5::InputError for radius <= 0, distance_factor <= 1 or zoom <= 0.
Camera orbit_camera(glm::vec3 center, float radius, const OrbitView& view);

}  // namespace pp5
