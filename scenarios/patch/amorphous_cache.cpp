#include "scenarios/patch/amorphous_cache.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "scenarios/patch/patch_test.hpp"

namespace debris {

namespace {

namespace fs = std::filesystem;

// FNV-1a, 64 bits: names the file; the full key stored inside decides whether it is the right one.
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string tag_number(double v) {
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}

}  // namespace

AmorphousSampleCache::AmorphousSampleCache(std::string directory, std::ostream& log)
    : directory_(std::move(directory)), log_(log) {}

std::string AmorphousSampleCache::stem(const AmorphousSpec& spec) const {
  std::ostringstream os;
  os << "amorphous_d0_" << tag_number(spec.d0) << "_s_" << tag_number(spec.material.scaling) << "_nu_"
     << tag_number(spec.material.poisson_ratio) << "_" << std::hex << std::setw(16) << std::setfill('0')
     << fnv1a(amorphous_spec_key(spec));
  return (fs::path(directory_) / os.str()).string();
}

std::string AmorphousSampleCache::source(const AmorphousSpec& spec) const {
  const auto it = entries_.find(amorphous_spec_key(spec));
  return it == entries_.end() ? std::string("not made yet") : it->second.source;
}

const AmorphousSampleFile& AmorphousSampleCache::get(const AmorphousSpec& spec) {
  const std::string key = amorphous_spec_key(spec);
  auto it = entries_.find(key);
  if (it == entries_.end()) {
    Entry e;
    const std::string st = stem(spec), h5 = st + ".h5";
    try {
      std::error_code ec;
      if (fs::exists(h5, ec)) {
        AmorphousSampleFile f = read_amorphous_sample(h5);
        if (f.input_echo == key) {
          e.file = std::move(f);
          e.source = "loaded from " + h5;
          e.ok = true;
          log_ << "  amorphous sample loaded from " << h5 << " (" << e.file.particles.size() << " particles)\n";
        } else {
          log_ << "  " << h5 << " holds another recipe: remade\n";
        }
      }
      if (!e.ok) {
        log_ << "  making the amorphous sample " << fs::path(st).filename().string() << " (d0 = " << spec.d0
             << " d_c, box " << spec.length << " x " << spec.length << " x " << spec.width << " d0) ..." << std::flush;
        const AmorphousSample made = make_amorphous_sample(spec);
        write_amorphous_sample(st, made, spec, key);
        e.file = read_amorphous_sample(h5);
        std::ostringstream os;
        os << std::setprecision(4) << "made in " << made.phase1_seconds + made.phase2_seconds << " s ("
           << made.particles.size() << " particles, volume fraction " << made.inserted_fraction << " -> "
           << made.relaxed_fraction << ", phase 2 " << made.phase2_steps << " steps, max |sigma_aa| "
           << made.final_max_stress << " E, deepest overlap after phase 1 " << made.phase1_max_overlap
           << " d_s), saved as " << st << ".h5/.data";
        e.ok = true;
        log_ << " " << os.str() << "\n";
        std::ostringstream src;
        src << std::setprecision(3) << "made in " << made.phase1_seconds + made.phase2_seconds << " s";
        e.source = src.str();
      }
    } catch (const InputError& err) {  // the relaxation did not converge, or the box became too thin
      e.error = err.what();
    } catch (const std::runtime_error& err) {  // a non-finite state
      e.error = err.what();
    }
    if (!e.ok) log_ << "\n  amorphous sample failed: " << e.error << "\n";
    it = entries_.emplace(key, std::move(e)).first;
  }
  if (!it->second.ok) throw PatchRunError("amorphous sample: " + it->second.error);
  return it->second.file;
}

}  // namespace debris
