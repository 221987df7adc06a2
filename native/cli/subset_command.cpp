// bakegi subset scene.bgs --count K --out subset.bgs [--indices idx.npy] [--seed S]:
// writes the same scene with K of its bake points, chosen uniformly at random without
// replacement (a seeded partial Fisher-Yates shuffle, indices kept in file order), and the
// chosen indices as float32 (exact below 2^24). A converged reference on a few thousand
// points of a large scene costs what a whole-scene reference cannot
// (tools/real_scenes.py compares every method there).
#include <algorithm>
#include <cstdio>
#include <numeric>
#include <vector>

#include "arguments.h"
#include "commands.h"
#include "exit_codes.h"
#include "npy_file.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

namespace {

// SplitMix64: a tiny, well-mixed generator; the choice must not depend on the platform's
// standard library.
uint64_t next_random(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace

int run_subset_command(const std::vector<std::string>& words) {
  const Arguments args(words, {{"count"}, {"out"}, {"indices"}, {"seed"}});
  if (args.positional().size() != 1) throw UsageError("subset expects one scene file");
  const auto out = args.value("out");
  if (!out) throw UsageError("subset needs --out subset.bgs");
  const int64_t wanted = args.int_value("count", -1, 1, int64_t(1) << 40);
  if (wanted < 1) throw UsageError("subset needs --count K (K >= 1)");
  uint64_t state = uint64_t(args.int_value("seed", 0, 0, INT64_MAX));

  const SceneFile file = load_scene_file_with_points(args.positional()[0]);
  const uint64_t count = bakegi_points_count(file.points.get());
  std::vector<float> positions(3 * count), normals(3 * count);
  std::vector<uint32_t> ids(count);
  check(bakegi_points_get(file.points.get(), positions.data(), normals.data(), ids.data()),
        "reading the bake points");
  const uint64_t k = std::min<uint64_t>(uint64_t(wanted), count);
  std::vector<uint64_t> order(count);
  std::iota(order.begin(), order.end(), uint64_t(0));
  for (uint64_t i = 0; i < k; ++i) {
    const uint64_t j = i + next_random(state) % (count - i);
    std::swap(order[i], order[j]);
  }
  order.resize(k);
  std::sort(order.begin(), order.end());

  std::vector<float> sub_positions, sub_normals, sub_indices;
  std::vector<uint32_t> sub_ids;
  for (uint64_t i : order) {
    sub_positions.insert(sub_positions.end(), &positions[3 * i], &positions[3 * i] + 3);
    sub_normals.insert(sub_normals.end(), &normals[3 * i], &normals[3 * i] + 3);
    sub_ids.push_back(ids[i]);
    sub_indices.push_back(float(i));
  }
  bakegi_points* raw = nullptr;
  check(bakegi_points_create(sub_positions.data(), sub_normals.data(), sub_ids.data(), k, &raw),
        "making the subset");
  const PointsHandle subset(raw);
  check(bakegi_file_write(out->c_str(), file.scene.get(), subset.get()), "writing " + *out);
  if (const auto path = args.value("indices")) {
    write_npy_float32(*path, sub_indices.data(), {k});
  }
  std::fprintf(stderr, "wrote %llu of %llu bake points to %s\n",
               static_cast<unsigned long long>(k), static_cast<unsigned long long>(count),
               out->c_str());
  return kExitOk;
}

}  // namespace bakegi::cli
