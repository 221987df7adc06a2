// A link of the antiradiance solver (§3.1–3.2): the unoccluded exchange from a sender element
// to a receiver element through one directional bin. Built by LinkRefinement, used by the
// global pass.
#pragma once

#include <cstdint>

namespace bakegi::antiradiance {

// Directions are stored as the direction light TRAVELS (from sender to receiver), for both
// ends: the sender's exitant bin and the receiver's incident bin are the same bin. So
// L_in(x, ω_j) is radiance travelling along ω_j (arriving from −ω_j), and Eq. 19's
// antiradiance I_A(x, ω_j) = a ⟨n|−ω_j⟩ L_in(x, ω_j) leaves the back side along ω_j.
struct Link {
  uint32_t receiver = 0;     // element index (ElementHierarchy::elements())
  uint32_t sender = 0;       // element index
  uint16_t bin = 0;          // DirectionalBins index of normalize(x_receiver − x_sender)
  uint8_t spread_class = 0;  // BinSpreading class of the sender's cone seen from the receiver
  uint8_t reserved = 0;
  float form_factor = 0.0f;  // Eq. 17: 1 / (|x_i − x_k|² ω_bin)
};

static_assert(sizeof(Link) == 16, "links are the bulk of the solver's memory");

}  // namespace bakegi::antiradiance
