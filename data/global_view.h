#pragma once
// The thesis's 360-degree "global view" (surround-aware SSGI, eq. 4.1 MergeToGlobalView):
// the six faces of a surround frame copied into one 4F x 2F image, F = face size
// (F = 256 gives the thesis's 1024x512). docs/global-view.md has the picture.
//
//          x: 0     F-h     2F-h     3F-h     4F-h     4F     (h = floor(F/2))
//   rows [0, T)       up, unrolled: each column looks from the pole to its face's edge
//   rows [T, T+F)   | back> | left  | front | right | <back |
//   rows [T+F, 2F)    down, unrolled the same way           (T = floor(F/2))
//
// Middle band: exact copies of the four side faces; the back face is split, its right
// part on the left edge and its left part on the right edge, so the band is a periodic
// panorama. Polar bands: the up (down) face is cut into four triangles by its diagonals;
// the triangle touching side face k is stretched over the band columns above (below)
// that face, row t running from the face centre (the pole, outer row) to the shared edge
// (inner row) — nearest-pixel copies, so pixels near the poles repeat (the thesis's
// "duplicate pixels"). Every boundary between neighbouring pixels is a boundary in 3-D
// too (test_global_view checks the angle between neighbours).
//
// Face orientations follow docs/dataset-format.md (front looks down -z, image up +y).
#include <array>
#include <cstdint>
#include <vector>

#include "core/tensor.h"
#include "data/dataset.h"

namespace nns::data {

struct PixelRect {
  int x0 = 0, y0 = 0, w = 0, h = 0;
};

// Camera-space basis of a face (front camera's space): a face pixel at normalised
// (s, r) in [0,1]^2 (s right, r down) looks along forward + (2s-1) right + (1-2r) up.
struct FaceBasis {
  std::array<float, 3> forward, right, up;
};
FaceBasis face_basis(Face f);
// Unit direction through the centre of pixel (px, py) of an F x F face.
std::array<float, 3> face_direction(Face f, int px, int py, int F);

class GlobalViewLayout {
 public:
  explicit GlobalViewLayout(int face_size);
  int face_size, width, height;
  int top_rows, bottom_rows;  // T and F - T
  PixelRect front_rect() const;
  // Where global pixel i = y * width + x comes from.
  Face source_face(int64_t i) const { return Face(face_[size_t(i)]); }
  int32_t source_pixel(int64_t i) const { return pixel_[size_t(i)]; }  // py * F + px

 private:
  std::vector<uint8_t> face_;
  std::vector<int32_t> pixel_;
};

// A shared, immutable layout per face size (building one costs ~8F^2 operations).
const GlobalViewLayout& global_view_layout(int face_size);

// faces[f] is an F x F plane of face f (Face order); out has 4F x 2F floats.
void merge_to_global_view(const std::array<const float*, 6>& faces, int face_size, float* out);

// The front face back out of global-view planes: (N, C, 2F, 4F) -> (N, C, F, F).
Tensor<float> extract_front(const Tensor<float>& global);

}  // namespace nns::data
