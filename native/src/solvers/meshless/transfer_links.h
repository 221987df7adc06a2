// The single-bounce transport operator T of the meshless method (Lehtinen et al. 2008, §3.1):
// a link T_ij carries the vector irradiance at receiver basis function B_i due to unit scalar
// irradiance in sender basis function B_j, one 3-vector per colour channel (the albedo of the
// surface in between colours it). Links are kept per receiver, sorted by sender.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi::meshless {

// Column c is the vector irradiance (W/m^2 per W/m^2 of sender irradiance) of channel c.
using LinkValue = glm::mat3;

// The size of a link in the paper's thresholds: its largest channel's vector length.
inline float link_magnitude(const LinkValue& value) {
  return glm::max(glm::max(glm::length(value[0]), glm::length(value[1])), glm::length(value[2]));
}

struct TransferLink {
  uint32_t sender;
  LinkValue value;
};

struct TransferOperator {
  // receivers[i] holds the kept links of receiver point i (index into the basis hierarchy),
  // sorted by sender; empty for receivers never refined or with no significant link.
  std::vector<std::vector<TransferLink>> receivers;
  uint32_t sender_count = 0;  // senders are points [0, sender_count) of the hierarchy

  size_t link_count() const {
    size_t n = 0;
    for (const auto& links : receivers) n += links.size();
    return n;
  }
  size_t memory_bytes() const {
    size_t bytes = receivers.capacity() * sizeof(std::vector<TransferLink>);
    for (const auto& links : receivers) bytes += links.capacity() * sizeof(TransferLink);
    return bytes;
  }
};

}  // namespace bakegi::meshless
