#pragma once
// Curved and generated meshes for the scene families (builder.h has the flat ones:
// quads, boxes, prisms, beams). Every function takes `smooth`: true stores per-vertex
// normals (Scene::normals, interpolated by the ray tracer) so a 24-sided column shades
// like a round one; false leaves the facets flat, as a low-poly asset would be. Both
// occur in real G-buffers, and a screen-space method must handle both.
//
// The vertex-normal array is kept in step with the positions: a mesh pads it with zero
// (= flat) normals for the vertices added before it, and make_family_scene() pads the
// end, so flat and smooth pieces mix freely in one scene.
#include <cstdint>
#include <functional>
#include <vector>

#include "core/rng.h"
#include "render/noise.h"  // value_noise, fbm: displacement
#include "render/scene.h"

namespace nns::render {

// A point of a lathe profile: distance from the axis and height along it.
struct ProfilePoint {
  float r, y;
};

// Surface of revolution about the axis from `base` along `axis` (unit): the profile
// swept through `segments` steps. A profile point on the axis (r = 0) becomes one
// vertex (a fan: caps, dome tops, cone apexes); a point repeated twice in a row makes
// a hard crease there (the smooth normals are averaged per vertex, and the repeat
// splits the vertex). `closed` joins the last profile point back to the first (torus).
void add_lathe(Scene& s, Vec3 base, Vec3 axis, const std::vector<ProfilePoint>& profile, int segments,
               uint32_t material, bool smooth, bool closed = false);

// Round shapes built on add_lathe (axis +y unless given).
void add_round_cylinder(Scene& s, Vec3 a, Vec3 b, float radius, int segments, uint32_t m, bool smooth,
                        bool caps = true);
void add_cone(Scene& s, Vec3 base, float radius, float height, int segments, uint32_t m, bool smooth);
void add_sphere(Scene& s, Vec3 centre, float radius, int segments, uint32_t m, bool smooth);
// Upper half of a sphere standing on `centre` (a dome, a bowl turned over).
void add_dome(Scene& s, Vec3 centre, float radius, int segments, uint32_t m, bool smooth);
// Ring of major radius R and tube radius r about `axis` through `centre`.
void add_torus(Scene& s, Vec3 centre, Vec3 axis, float R, float r, int segments, int tube_segments, uint32_t m,
               bool smooth);

// Box of half-size `half` with edges and corners rounded to radius `bevel`
// (< min(half)), turned by `yaw` about +y. Seam vertices are computed component by
// component in the same order from either face, so adjacent faces share bit-identical
// positions and Embree's robust mode leaves no crack for AO rays to leak through.
void add_bevelled_box(Scene& s, Vec3 centre, Vec3 half, float bevel, float yaw, uint32_t m, bool smooth,
                      int arc_steps = 3);

// Icosphere subdivided `levels` times, each vertex pushed out radially by
// radius * (1 + displace(unit direction)): rocks, blobs, boulders. Vertices are
// shared, so smooth normals are area-weighted face-normal averages.
void add_displaced_sphere(Scene& s, Vec3 centre, Vec3 radii, int levels, const std::function<float(Vec3)>& displace,
                          uint32_t m, bool smooth);

// Height field y = y0 + height(x, z) over [x0, x1] x [z0, z1] in nx x nz cells.
void add_height_field(Scene& s, float x0, float x1, float z0, float z1, int nx, int nz,
                      const std::function<float(float, float)>& height, uint32_t m, bool smooth);

// A prism with a 2D cross-section between two polylines `outer` and `inner` (same
// length): the strip between them is the face at both ends, and it is extruded from
// `origin` along `depth`. (u, v) of the cross-section map to origin + u*eu + v*ev.
// Arches (outer: a rectangle's edge, inner: a half circle) and vault shells (two
// concentric arcs) are this.
// The inner and outer walls are smooth (vertex normals averaged along the polyline)
// when their flag says so; the two end faces and the two end walls are always flat.
void add_band_extrusion(Scene& s, const std::vector<ProfilePoint>& outer, const std::vector<ProfilePoint>& inner,
                        Vec3 origin, Vec3 eu, Vec3 ev, Vec3 depth, uint32_t m, bool smooth_inner, bool smooth_outer);

// A groin vault over the square bay [-R, R]^2 around `centre` (at springing height):
// the union of two barrel vaults of radius R crossing at right angles, seen from
// below — four cylindrical webs meeting in diagonal groins (hard creases).
void add_groin_vault(Scene& s, Vec3 centre, float R, int steps, uint32_t m, bool smooth);

// Area-weighted average of the face normals of triangles [first_triangle, end) into
// the normals of their vertices (which must all be >= first_vertex). Used by the
// builders above; exposed for meshes assembled by hand.
void smooth_normals(Scene& s, uint32_t first_vertex, size_t first_triangle);

// Pads Scene::normals with zero (flat) normals up to the current vertex count.
inline void pad_normals(Scene& s) { s.normals.resize(s.positions.size()); }

}  // namespace nns::render
