// The subcommands of `bakegi`. Each takes the words after its name and returns an exit
// code (exit_codes.h); errors are thrown as UsageError, CoreError, FileError or JsonError
// and turned into messages and exit codes by main().
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace bakegi::cli {

int run_bake_command(const std::vector<std::string>& args);
int run_sweep_command(const std::vector<std::string>& args);
int run_info_command(const std::vector<std::string>& args);
int run_compare_command(const std::vector<std::string>& args);
int run_points_command(const std::vector<std::string>& args);
int run_relight_command(const std::vector<std::string>& args);
int run_converge_command(const std::vector<std::string>& args);
int run_subset_command(const std::vector<std::string>& args);
int run_settings_command(const std::vector<std::string>& args);
int run_grid_command(const std::vector<std::string>& args);
int run_web_command(const std::vector<std::string>& args);
int run_serve_command(const std::vector<std::string>& args);
int run_preview_command(const std::vector<std::string>& args);

// Loads an (n, 3) array and checks n against the expected bake point count.
std::vector<float> load_rgb_array(const std::string& path, uint64_t expected_points);

}  // namespace bakegi::cli
