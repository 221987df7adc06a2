#include "solvers/antiradiance/push_pull.h"

#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"

namespace bakegi::antiradiance {

namespace {

// Between cancel checks: 256 rows of up to 3072 bins, well under a millisecond.
constexpr uint32_t kElementsPerCancelCheck = 256;

// Subtrees of at most this many elements are walked by one task: large enough that the
// sequential part near the root is a few hundred elements for the Cornell box default.
constexpr uint32_t kSubtreeGrain = 512;

// The elements above the parallel subtrees, parents before children, and the subtree roots.
struct TreeSplit {
  std::vector<uint32_t> upper;
  std::vector<uint32_t> subtrees;
};

TreeSplit split_tree(const std::vector<Element>& elements) {
  TreeSplit split;
  if (elements.empty()) return split;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t e = stack.back();
    stack.pop_back();
    const Element& element = elements[e];
    if (element.subtree_end - e <= kSubtreeGrain || element.child_count == 0) {
      split.subtrees.push_back(e);
      continue;
    }
    split.upper.push_back(e);
    for (uint32_t c = element.first_child, k = 0; k < element.child_count;
         ++k, c = elements[c].subtree_end) {
      stack.push_back(c);
    }
  }
  return split;
}

void check_tables(const ElementHierarchy& hierarchy, const RadianceTables& tables) {
  if (tables.element_count() != hierarchy.element_count()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "radiance tables do not match the hierarchy");
  }
}

void add_parent_radiance(const std::vector<Element>& elements, RadianceTables& tables, uint32_t e) {
  const uint32_t parent = elements[e].parent;
  if (parent == kNoElement) return;
  const std::span<const glm::vec3> from = tables.incident(parent);
  const std::span<glm::vec3> to = tables.incident(e);
  for (size_t b = 0; b < to.size(); ++b) to[b] += from[b];
}

void sum_children_intensity(const std::vector<Element>& elements, RadianceTables& tables,
                            uint32_t e) {
  const Element& element = elements[e];
  if (element.child_count == 0) return;
  const std::span<glm::vec3> to = tables.exitant(e);
  uint32_t c = element.first_child;
  const std::span<const glm::vec3> first = tables.exitant(c);
  std::copy(first.begin(), first.end(), to.begin());
  for (uint32_t k = 1; k < element.child_count; ++k) {
    c = elements[c].subtree_end;
    const std::span<const glm::vec3> child = tables.exitant(c);
    for (size_t b = 0; b < to.size(); ++b) to[b] += child[b];
  }
}

}  // namespace

void push(const ElementHierarchy& hierarchy, RadianceTables& tables, const JobContext* context) {
  check_tables(hierarchy, tables);
  const std::vector<Element>& elements = hierarchy.elements();
  const TreeSplit split = split_tree(elements);
  for (uint32_t e : split.upper) add_parent_radiance(elements, tables, e);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, split.subtrees.size(), 1),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t s = block.begin(); s != block.end(); ++s) {
                        const uint32_t root = split.subtrees[s];
                        for (uint32_t e = root; e != elements[root].subtree_end; ++e) {
                          if (context && e % kElementsPerCancelCheck == 0) {
                            context->throw_if_cancelled();
                          }
                          add_parent_radiance(elements, tables, e);
                        }
                      }
                    });
}

void pull(const ElementHierarchy& hierarchy, RadianceTables& tables, const JobContext* context) {
  check_tables(hierarchy, tables);
  const std::vector<Element>& elements = hierarchy.elements();
  const TreeSplit split = split_tree(elements);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, split.subtrees.size(), 1),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t s = block.begin(); s != block.end(); ++s) {
                        const uint32_t root = split.subtrees[s];
                        for (uint32_t e = elements[root].subtree_end; e-- != root;) {
                          if (context && e % kElementsPerCancelCheck == 0) {
                            context->throw_if_cancelled();
                          }
                          sum_children_intensity(elements, tables, e);
                        }
                      }
                    });
  if (context) context->throw_if_cancelled();
  for (auto it = split.upper.rbegin(); it != split.upper.rend(); ++it) {
    sum_children_intensity(elements, tables, *it);
  }
}

}  // namespace bakegi::antiradiance
