// volillum-render: checking the header of a NRRD or MetaImage file before a VTK reader sees it.
// vtkNrrdReader and MetaIO trust their headers: a garbled type, a missing or misplaced size,
// a one-axis image or a bad data file pattern makes them crash, hang or read garbage.
#include "VolIllumRender.h"

#include "vtkIlluminationVolumeAlgorithm.h"

#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

namespace volillum_render
{

namespace
{
// Largest number of points the tool reads, and of values per point (a NRRD vector axis,
// MetaImage channels).
constexpr long long MaximumPoints = vtkIlluminationVolumeAlgorithm::MaximumOutputPoints;
constexpr long long MaximumComponents = 16;

// The scalar types vtkNrrdReader and vtkMetaImageReader know.
const char* const NrrdTypes[] = { "signed char", "int8", "int8_t", "uchar", "unsigned char",
  "uint8", "uint8_t", "short", "short int", "signed short", "signed short int", "int16", "int16_t",
  "ushort", "unsigned short", "unsigned short int", "uint16", "uint16_t", "int", "signed int",
  "int32", "int32_t", "uint", "unsigned int", "uint32", "uint32_t", "longlong", "long long",
  "long long int", "signed long long", "signed long long int", "int64", "int64_t", "ulonglong",
  "unsigned long long", "unsigned long long int", "uint64", "uint64_t", "float", "double" };
const char* const MetaTypes[] = { "MET_CHAR", "MET_UCHAR", "MET_SHORT", "MET_USHORT", "MET_INT",
  "MET_UINT", "MET_LONG", "MET_ULONG", "MET_LONG_LONG", "MET_ULONG_LONG", "MET_FLOAT",
  "MET_DOUBLE" };
// The encodings vtkNrrdReader reads (lower case).
const char* const NrrdEncodings[] = { "raw", "ascii", "text", "txt", "gzip", "gz" };

template <size_t N>
bool OneOf(const std::string& value, const char* const (&names)[N])
{
  return std::find(std::begin(names), std::end(names), value) != std::end(names);
}

// text in quotes, bytes outside printable ASCII as \xNN (the refusal stays one line).
std::string Quote(const std::string& text)
{
  std::string quoted = "'";
  for (const unsigned char c : text.substr(0, 40))
  {
    char escaped[5];
    std::snprintf(escaped, sizeof(escaped), "\\x%02x", c);
    quoted += (c >= 0x20 && c < 0x7f) ? std::string(1, static_cast<char>(c)) : escaped;
  }
  return quoted + (text.size() > 40 ? "...'" : "'");
}

std::string Trim(const std::string& s)
{
  const size_t begin = s.find_first_not_of(" \t\r");
  return begin == std::string::npos ? "" : s.substr(begin, s.find_last_not_of(" \t\r") + 1 - begin);
}

std::vector<std::string> Words(const std::string& s)
{
  std::istringstream in(s);
  std::vector<std::string> words;
  for (std::string word; in >> word;)
  {
    words.push_back(word);
  }
  return words;
}

// The first word of text ("" when none).
std::string First(const std::string& text)
{
  const std::vector<std::string> words = Words(text);
  return words.empty() ? "" : words[0];
}

// Whether text is exactly a whole number (digits, maybe a minus) in [low, high].
bool Whole(const std::string& text, long long low, long long high, long long& value)
{
  const size_t sign = text.compare(0, 1, "-") == 0 ? 1 : 0;
  if (text.size() <= sign || text.size() > 18 ||
    text.find_first_not_of("0123456789", sign) != std::string::npos)
  {
    return false;
  }
  value = std::stoll(text);
  return value >= low && value <= high;
}

// What was read of a header: its fields in order and the lines after them (the names of a
// LIST of data files).
struct Header
{
  std::string Path;
  std::string Format;
  std::vector<std::pair<std::string, std::string>> Fields;
  std::vector<std::string> Rest;

  [[noreturn]] void Refuse(const std::string& problem) const
  {
    Fail(this->Path + ": bad " + this->Format + " header: " + problem);
  }

  // The value of a field (the last one of that name), or nullptr.
  const std::string* Find(const std::string& name) const
  {
    for (auto field = this->Fields.rbegin(); field != this->Fields.rend(); ++field)
    {
      if (field->first == name)
      {
        return &field->second;
      }
    }
    return nullptr;
  }

  const std::string& Require(const std::string& name) const
  {
    const std::string* value = this->Find(name);
    if (!value)
    {
      this->Refuse("no '" + name + "' field");
    }
    return *value;
  }

  // The sizes of the axes: count whole numbers from 1 to MaximumPoints (their product is
  // checked against the tool's limit once the reader has read the header).
  std::vector<long long> Sizes(const std::string& field, size_t count) const
  {
    const std::string& text = this->Require(field);
    const std::vector<std::string> words = Words(text);
    if (words.size() != count)
    {
      this->Refuse(field + " " + Quote(text) + " has " + std::to_string(words.size()) +
        " values for " + std::to_string(count) + " axes");
    }
    std::vector<long long> sizes(count);
    for (size_t a = 0; a < count; ++a)
    {
      if (!Whole(words[a], 1, MaximumPoints, sizes[a]))
      {
        this->Refuse(field + " " + Quote(text) + ": each size must be a whole number from 1 to " +
          std::to_string(MaximumPoints));
      }
    }
    return sizes;
  }

  // The data files named by value, beside the header: one file, a LIST (the lines after the
  // field) or a pattern "format first last step [axis]"; a list or pattern names one file
  // per slice, slices of the last axis. Each file must exist.
  void CheckDataFiles(const std::string& value, long long slices, bool pattern) const
  {
    const std::vector<std::string> words = Words(value);
    std::vector<std::string> names;
    const bool list = !words.empty() && words[0] == "LIST";
    if (list)
    {
      for (size_t i = 0; i < this->Rest.size() && !Trim(this->Rest[i]).empty(); ++i)
      {
        names.push_back(Trim(this->Rest[i]));
      }
    }
    else if (pattern)
    {
      const std::string format = words.empty() ? "" : words[0];
      const size_t conversion = format.find('%');
      const size_t type = format.find_first_not_of("0123456789", conversion + 1);
      long long first = 0, last = 0, step = 0, axis = 0;
      if (words.size() < 4 || words.size() > 5 || format.size() > 200 ||
        conversion == std::string::npos || type == std::string::npos || type > conversion + 3 ||
        format[type] != 'd' || format.find('%', type) != std::string::npos ||
        !Whole(words[1], 0, INT_MAX, first) || !Whole(words[2], first, INT_MAX, last) ||
        !Whole(words[3], 1, INT_MAX, step) || (words.size() == 5 && !Whole(words[4], 1, 4, axis)))
      {
        this->Refuse("data file " + Quote(value) +
          " is not 'format first last step [axis]' with one %d in the format, first <= last and "
          "a positive step");
      }
      if ((last - first) / step + 1 != slices)
      {
        this->Refuse("data file " + Quote(value) + " names " +
          std::to_string((last - first) / step + 1) + " files for " + std::to_string(slices) +
          " slices");
      }
      std::vector<char> name(format.size() + 128);
      for (long long i = first; i <= last; i += step)
      {
        std::snprintf(name.data(), name.size(), format.c_str(), static_cast<int>(i));
        names.emplace_back(name.data());
      }
    }
    else
    {
      names.push_back(value);
    }
    if ((list || names.size() > 1) && static_cast<long long>(names.size()) != slices)
    {
      this->Refuse("data file " + Quote(value) + " lists " + std::to_string(names.size()) +
        " files for " + std::to_string(slices) + " slices");
    }
    const std::string folder = vtksys::SystemTools::GetParentDirectory(this->Path);
    for (const std::string& name : names)
    {
      const std::string path = vtksys::SystemTools::CollapseFullPath(name, folder);
      if (name.empty() || !std::ifstream(path, std::ios::binary) ||
        vtksys::SystemTools::FileIsDirectory(path))
      {
        this->Refuse("data file " + Quote(name) + " cannot be read");
      }
    }
  }
};

// The first bytes of a file (as many as vtkNrrdReader reads for its header) as lines.
std::vector<std::string> HeadLines(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::string head(1 << 22, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  std::vector<std::string> lines;
  std::istringstream text(head);
  for (std::string line; std::getline(text, line);)
  {
    lines.push_back(line.empty() || line.back() != '\r' ? line : line.substr(0, line.size() - 1));
  }
  return lines;
}

// The fields of a NRRD header's lines after the first (h.Fields, and h.Rest: the data files
// listed after 'data file: LIST'); returns the 'dimension' field's value (0 when there is
// none).
size_t ReadNrrdFields(Header& h, const std::vector<std::string>& lines)
{
  // The number of axes vtkNrrdReader expects in a per-axis field: the dimension, 3 after a
  // 'space' field or that of a 'space dimension'.
  size_t axes = 0, declared = 0;
  for (size_t i = 1; i < lines.size() && !lines[i].empty(); ++i)
  {
    const std::string& line = lines[i];
    const size_t colon = line.find(": "), keyValue = line.find(":=");
    if (line[0] == '#' || keyValue < colon)
    {
      continue; // a comment or a key/value pair
    }
    if (colon == std::string::npos || colon == 0 ||
      line.find_first_not_of("abcdefghijklmnopqrstuvwxyz ") < colon)
    {
      h.Refuse("line " + std::to_string(i + 1) + " " + Quote(line) + " is not 'field: value'");
    }
    const std::string name = line.substr(0, colon), value = Trim(line.substr(colon + 2));
    if (value.empty())
    {
      h.Refuse("field '" + name + "' has no value");
    }
    h.Fields.emplace_back(name, value);
    long long number = 0;
    if (name == "dimension" || name == "space dimension")
    {
      if (!Whole(value, 1, 4, number))
      {
        h.Refuse(name + " " + Quote(value) + " is not a whole number from 1 to 4");
      }
      axes = static_cast<size_t>(number);
      declared = name == "dimension" ? axes : declared;
    }
    else if (name == "space")
    {
      axes = 3;
    }
    else if ((name == "sizes" || name == "spacings") && (Words(value).size() != axes || !declared))
    {
      h.Refuse(name + " " + Quote(value) + " has " + std::to_string(Words(value).size()) +
        " values where vtkNrrdReader expects " + std::to_string(axes) +
        " (the dimension, given before it; 3 after a 'space' field)");
    }
    else if ((name == "data file" || name == "datafile") && First(value) == "LIST")
    {
      h.Rest.assign(lines.begin() + static_cast<std::ptrdiff_t>(i) + 1, lines.end());
      break; // the names of the data files run to the end of the header
    }
  }
  return declared;
}

// A NRRD header's sample type, encoding and byte order, as vtkNrrdReader reads them.
void CheckNrrdEncoding(Header& h)
{
  const std::string& type = h.Require("type");
  if (!OneOf(type, NrrdTypes))
  {
    h.Refuse("type " + Quote(type) + " is not one vtkNrrdReader reads");
  }
  const std::string encoding = Lower(h.Require("encoding"));
  if (!OneOf(encoding, NrrdEncodings))
  {
    h.Refuse("encoding " + Quote(encoding) + " is not raw, gzip, gz, ascii, text or txt");
  }
  const std::string* endian = h.Find("endian");
  if (endian && *endian != "little" && *endian != "big")
  {
    h.Refuse("endian " + Quote(*endian) + " is not little or big");
  }
}

// A NRRD header's sizes (the first axis as vector components or not, 2 or 3 spatial axes;
// declared: the dimension) and its data files.
void CheckNrrdAxesAndData(Header& h, size_t declared)
{
  const std::vector<long long> sizes = h.Sizes("sizes", declared);
  const std::string* spacings = h.Find("spacings");
  const std::string* directions = h.Find("space directions");
  const bool vector = declared == 4 || sizes[0] <= 9 ||
    (spacings && std::strtod(First(*spacings).c_str(), nullptr) == 0.0) ||
    (directions && First(*directions) == "none");
  if (vector && sizes[0] > MaximumComponents)
  {
    h.Refuse("the first axis of sizes " + Quote(h.Require("sizes")) + " would be " +
      std::to_string(sizes[0]) + " vector components (at most " +
      std::to_string(MaximumComponents) + ")");
  }
  if (declared - vector < 2 || declared - vector > 3)
  {
    h.Refuse("sizes " + Quote(h.Require("sizes")) + " leave " + std::to_string(declared - vector) +
      " spatial axes (vtkNrrdReader takes a first axis of 9 or fewer samples as vector "
      "components); 2 or 3 are needed");
  }
  const std::string* dataFile = h.Find("data file") ? h.Find("data file") : h.Find("datafile");
  if (dataFile)
  {
    h.CheckDataFiles(*dataFile, sizes.back(), Words(*dataFile).size() >= 4);
  }
  else if (EndsWith(Lower(h.Path), ".nhdr"))
  {
    h.Refuse("no 'data file' field in a detached header");
  }
}

// NRRD: "NRRD000N", then "field: value" lines and comments up to a blank line (or the end of
// a detached header); vtkNrrdReader takes a first axis of 9 or fewer samples (all of them in
// 4D, or one with no spacing) as the components of a vector.
void CheckNrrd(Header& h)
{
  const std::vector<std::string> lines = HeadLines(h.Path);
  if (lines.empty() || lines[0].size() != 8 || lines[0].compare(0, 4, "NRRD") != 0 ||
    lines[0].find_first_not_of("0123456789", 4) != std::string::npos)
  {
    h.Refuse("the first line " + Quote(lines.empty() ? "" : lines[0]) + " is not NRRD000N");
  }
  const size_t declared = ReadNrrdFields(h, lines);
  CheckNrrdEncoding(h);
  h.Require("dimension");
  CheckNrrdAxesAndData(h, declared);
}

// MetaImage: "Key = Value" lines up to ElementDataFile, the last field.
void CheckMetaImage(Header& h)
{
  const std::vector<std::string> lines = HeadLines(h.Path);
  size_t dimensions = 0;
  for (size_t i = 0; i < lines.size(); ++i)
  {
    const std::string line = Trim(lines[i]);
    if (line.empty())
    {
      continue;
    }
    const size_t equals = line.find('=');
    const std::string key = Trim(line.substr(0, equals));
    const std::string value = equals == std::string::npos ? "" : Trim(line.substr(equals + 1));
    if (equals == std::string::npos || key.empty() ||
      key.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_") !=
        std::string::npos)
    {
      h.Refuse("line " + std::to_string(i + 1) + " " + Quote(line) + " is not 'Key = Value'");
    }
    h.Fields.emplace_back(key, value);
    long long number = 0;
    if (key == "NDims")
    {
      if (!Whole(value, 2, 3, number))
      {
        h.Refuse("NDims " + Quote(value) + " is not 2 or 3");
      }
      dimensions = static_cast<size_t>(number);
    }
    else if (key == "DimSize" && !dimensions)
    {
      h.Refuse("DimSize comes before NDims");
    }
    else if (key == "ElementNumberOfChannels" && !Whole(value, 1, MaximumComponents, number))
    {
      h.Refuse("ElementNumberOfChannels " + Quote(value) + " is not a whole number from 1 to " +
        std::to_string(MaximumComponents));
    }
    else if ((key == "CompressedData" || key == "BinaryData" || key == "ElementByteOrderMSB" ||
               key == "BinaryDataByteOrderMSB") &&
      Lower(value) != "true" && Lower(value) != "false")
    {
      h.Refuse(key + " " + Quote(value) + " is not True or False");
    }
    else if (key == "ElementDataFile")
    {
      h.Rest.assign(lines.begin() + static_cast<std::ptrdiff_t>(i) + 1, lines.end());
      break; // the last field: the voxels (or a LIST of data files) follow
    }
  }
  const std::string& type = h.Require("ElementType");
  if (!OneOf(type, MetaTypes))
  {
    h.Refuse("ElementType " + Quote(type) + " is not one vtkMetaImageReader reads");
  }
  h.Require("NDims");
  const std::vector<long long> sizes = h.Sizes("DimSize", dimensions);
  const std::string& dataFile = h.Require("ElementDataFile");
  if (Lower(dataFile) != "local")
  {
    h.CheckDataFiles(dataFile, sizes.back(), dataFile.find('%') != std::string::npos);
  }
}
}

void CheckVolumeHeader(const std::string& path)
{
  const std::string name = Lower(path);
  Header header{ path, "", {}, {} };
  if (EndsWith(name, ".nrrd") || EndsWith(name, ".nhdr"))
  {
    header.Format = "NRRD";
    CheckNrrd(header);
  }
  else if (EndsWith(name, ".mha") || EndsWith(name, ".mhd"))
  {
    header.Format = "MetaImage";
    CheckMetaImage(header);
  }
}

}
