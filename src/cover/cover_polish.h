#pragma once
// Private to the covering bake (cover.cpp): the volume polish, which lowers the union's
// volume without raising any ball's protrusion above a cap. Derivation in cover_polish.cpp.

#include "cover_elements.h"
#include "medspheres/mesh/mesh_query.h"

namespace medspheres::detail {

// From \p c (every element of \p e held by its owner, every ball protruding at most \p cap):
// each ball's centre moved by a pattern search, its radius what its own elements need there;
// a move is kept when the union's volume falls and the ball protrudes at most \p cap (by
// probe's signed distance). Each sweep over the balls ends with a shrink; at most \p sweeps
// of them, stopping early when one lowers the union by less than 1e-3 of itself. Every
// element stays held by its owner and the union never grows. Uses and keeps c.settled (the
// marks of the elements no moved ball may hold are still right). The same result for every
// \p threads (balls searched at once are chosen so that their searches are independent).
Clustering volume_polish(const MeshQuery& query, const Elements& e, Clustering c, double cap,
                         int sweeps, int threads);

}  // namespace medspheres::detail
