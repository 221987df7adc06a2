// How a method's precomputation becomes bytes and back, so that the job can keep it in a
// cache file (bake/precomputation_store.h owns the file: its key, header, checksum, atomic
// write, and what a stale or damaged file does). A method gets caching by returning a codec
// from Solver::codec() and declaring a "cache_dir" setting; the payload is all it writes.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace bakegi {

class ByteReader;
class ByteWriter;
class JobContext;
class Precomputation;
class Report;
class Settings;

class PrecomputationCodec {
 public:
  virtual ~PrecomputationCodec() = default;
  // Names the files ("<name>-<16 hex digits>.bgcache") and the report keys ("<name>_cache").
  virtual std::string name() const = 0;
  // The file's eighth magic byte ("BAKEGI\0" then this), one per method.
  virtual char magic() const = 0;
  // Bump when the payload or what the precomputation computes changes: older files then
  // miss (the version is part of the key) and are refused if read.
  virtual uint32_t version() const = 0;
  // Whether the bake points shaped the precomputation (they are then part of the key).
  virtual bool keyed_by_points(const Settings& settings) const = 0;

  virtual void encode(const Precomputation& precomputation, ByteWriter& payload) const = 0;
  // Reads a payload whose checksum and key matched. Throws Error(BAD_FILE) through `payload`
  // when it is inconsistent; `job` (optional) is checked for cancel while rebuilding.
  virtual std::shared_ptr<const Precomputation> decode(ByteReader& payload,
                                                       const JobContext* job) const = 0;
  // Adds what a loaded precomputation says of itself to the report (its statistics).
  virtual void report_loaded(const Precomputation&, Report&) const {}
};

}  // namespace bakegi
