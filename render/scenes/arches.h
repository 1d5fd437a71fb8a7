#pragma once
// The classical parts of the architectural families (defined in
// families_architecture.cpp): round columns, arch pieces and barrel vaults.
#include "render/scenes/family_kit.h"

namespace nns::render {

// A round column standing on `base`: a square plinth, a half-round base moulding, a
// shaft of radius r with entasis, a capital flaring to a square abacus (1.4 r half-size)
// at height h.
void add_column(Scene& s, Vec3 base, float r, float h, uint32_t m, const SceneStyle& st);

// The wall piece above one opening: a half-circle arch of radius r in a rectangle
// span x rise (the arch centred at u = 0, springing at v = 0), extruded along `depth`.
void add_arch_piece(Scene& s, Vec3 origin, Vec3 eu, Vec3 ev, Vec3 depth, float span, float rise, float r, int steps,
                    uint32_t m, const SceneStyle& st);

// Half-round barrel vault shell of inner radius r and thickness th, its axis along
// `axis` (unit, horizontal) from `start` for `len`, springing at start's height.
void add_barrel_vault(Scene& s, Vec3 start, Vec3 axis, float len, float r, float th, int steps, uint32_t m,
                      const SceneStyle& st);

}  // namespace nns::render
