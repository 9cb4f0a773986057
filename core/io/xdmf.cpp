#include "core/io/xdmf.hpp"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "core/error.hpp"

namespace debris::xdmf {

namespace {

/// Shortest text that reads back as the same double.
std::string number(double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

void data_item(std::string& x, const std::string& dims, const char* number_type, int precision,
               const std::string& ref) {
  x += "          <DataItem Dimensions=\"" + dims + "\" NumberType=\"" + number_type + "\" Precision=\"" +
       std::to_string(precision) + "\" Format=\"HDF\">" + ref + "</DataItem>\n";
}

}  // namespace

void check_stem(const std::string& stem) {
  if (stem.empty() || stem.find_first_of(":/") != std::string::npos)
    throw input_error("output", stem, "a trajectory file stem must be non-empty and hold neither ':' nor '/'");
}

std::string escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string begin(const std::string& collection) {
  return "<?xml version=\"1.0\" ?>\n"
         "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
         "<Xdmf Version=\"2.0\">\n"
         "  <Domain>\n"
         "    <Grid Name=\"" +
         collection + "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

void begin_frame(std::string& x, long step, double time, const std::string& n, const std::string& position_ref) {
  x += "      <Grid Name=\"step " + std::to_string(step) + "\" GridType=\"Uniform\">\n";
  x += "        <Time Value=\"" + number(time) + "\"/>\n";
  x += "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + n + "\"/>\n";
  x += "        <Geometry GeometryType=\"XYZ\">\n";
  data_item(x, n + " 3", "Float", 8, position_ref);
  x += "        </Geometry>\n";
}

void attribute(std::string& x, const char* name, bool vector, const std::string& n, const char* number_type,
               int precision, const std::string& ref) {
  x += std::string("        <Attribute Name=\"") + name + "\" AttributeType=\"" + (vector ? "Vector" : "Scalar") +
       "\" Center=\"Node\">\n";
  data_item(x, vector ? n + " 3" : n, number_type, precision, ref);
  x += "        </Attribute>\n";
}

void end_frame(std::string& x) { x += "      </Grid>\n"; }

void end(std::string& x) { x += "    </Grid>\n  </Domain>\n</Xdmf>\n"; }

void replace_file(const std::string& path, const std::string& text, const char* what) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw output_error(tmp, std::string("cannot open for writing: ") + std::strerror(errno));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw output_error(tmp, std::string(what) + ": writing failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw output_error(path, std::string(what) + ": cannot rename " + tmp + " onto it: " + std::strerror(errno));
}

}  // namespace debris::xdmf
