#include "scenarios/common/dem/height_map_output.hpp"

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "core/io/hdf5_file.hpp"

namespace debris {

namespace {

void write_field(h5::Location& at, const std::string& name, const HeightField& f) {
  at.write(name, f.h, static_cast<std::size_t>(f.n_a), static_cast<std::size_t>(f.n_b));
}

void write_layout(h5::File& file, const HeightField& f) {
  file.set_attribute("normal_axis", static_cast<std::int32_t>(f.normal_axis));
  file.set_attribute("axis_a", static_cast<std::int32_t>(f.axis_a()));
  file.set_attribute("axis_b", static_cast<std::int32_t>(f.axis_b()));
  file.set_attribute("spacing", std::vector<double>{f.spacing_a(), f.spacing_b()});
  file.set_attribute("origin", std::vector<double>{f.origin_a, f.origin_b});
}

}  // namespace

HeightMapWriter::HeightMapWriter(std::string path, long keep) : path_(std::move(path)) {
  if (keep < 0 || !std::filesystem::exists(path_)) {
    if (keep > 0)
      throw std::runtime_error(path_ + ": missing, but the run continues from " + std::to_string(keep) +
                               " census samples");
    h5::File f(path_, h5::File::Mode::create);
    f.create_group("samples");
    f.close();
    return;
  }
  // Copy the samples to keep into a fresh file, then put it in place.
  const std::string tmp = path_ + ".tmp";
  {
    h5::File old(path_, h5::File::Mode::read_only);
    h5::File out(tmp, h5::File::Mode::create);
    for (const char* a : {"normal_axis", "axis_a", "axis_b"})
      if (old.has_attribute(a)) out.set_attribute(a, old.attribute<std::int32_t>(a));
    for (const char* a : {"spacing", "origin"})
      if (old.has_attribute(a)) out.set_attribute(a, old.attribute_array<double>(a));
    {  // the groups close before the files
      h5::Group from = old.open_group("samples");
      h5::Group to = out.create_group("samples");
      for (long k = 0; k < keep; ++k) {
        const std::string name = std::to_string(k);
        if (!from.has(name))
          throw std::runtime_error(path_ + ": holds " + std::to_string(k) + " census samples; the run continues from " +
                                   std::to_string(keep));
        h5::Group s = from.open_group(name);
        h5::Group d = to.create_group(name);
        d.set_attribute("step", s.attribute<std::int64_t>("step"));
        d.set_attribute("time", s.attribute<double>("time"));
        d.set_attribute("slide", s.attribute<double>("slide"));
        for (const char* face : {"bottom", "top"}) {
          const h5::Array<double> a = s.read<double>(face);
          d.write(face, a.values, a.shape.at(0), a.shape.at(1));
        }
      }
    }
    out.close();
  }
  std::filesystem::rename(tmp, path_);
  samples_ = keep;
}

void HeightMapWriter::append(long step, double time, double slide, const HeightField& bottom, const HeightField& top) {
  h5::File f(path_, h5::File::Mode::read_write);
  if (samples_ == 0) write_layout(f, bottom);
  {  // the group closes before the file (close() checks that nothing of it stays open)
    h5::Group s = f.open_group("samples").create_group(std::to_string(samples_));
    s.set_attribute("step", static_cast<std::int64_t>(step));
    s.set_attribute("time", time);
    s.set_attribute("slide", slide);
    write_field(s, "bottom", bottom);
    write_field(s, "top", top);
  }
  f.close();
  ++samples_;
}

}  // namespace debris
