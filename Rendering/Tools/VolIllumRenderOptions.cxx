// volillum-render: the command line.
#include "VolIllumRender.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>

namespace volillum_render
{

namespace
{
const char* const Usage = R"(usage: volillum-render [options] [volume or grid]

Reads a volume (.vti .vtk .mha .mhd .nrrd .nhdr .slc .nii .nii.gz) or an unstructured
grid (.vtu .vtk .ex2 .exo .e), computes its illumination, renders it lit and writes a
PNG. Volumes use --method; grids the two-level unstructured solver and projected
tetrahedra. Without an input, --phantom chooses a generated volume.

options:
  --phantom NAME     ct (default), spheres, slab or chirp: generate the volume instead
  --dims N           phantom size (points per axis, default 128)
  --config FILE      JSON settings (see below); flags given after it override it
  --output FILE      PNG to write (default volillum.png)
  --method NAME      illumination method: propagation (multi-light illumination
                     volume, default), filtered (soft shadows from summed-area tables)
                     or reference (brute-force ray marching)
  --scale S          illumination resolution scale 1, 0.5 or 0.25 (default 1)
  --size W H         image size in pixels (default 512 512)
  --help             this text

JSON (every key optional; the value shown is the default):
  {"method": "propagation", "resolution_scale": 1, "image_size": [512, 512],
   "output": "volillum.png", "ambient": 0.1, "diffuse": 1.0, "background": [0,0,0],
   "gradient_shading": false, "chromatic_attenuation": false, "filter_width": 3,
   "ambient_occlusion": 0, "ambient_occlusion_radius": 0,
   "side_by_side": false, "labels": true, "component": -1,
   "lights": [{"type": "directional" | "point" | "spot",
               "position": [0.5,0.5,2], "focal_point": [0.5,0.5,0.5], "relative": false,
               "color": [1,1,1], "intensity": 1, "cone_angle": 30, "exponent": 1,
               "on": true, "radius": 0}],
   "transfer_function": {"color": [[s,r,g,b], ...], "opacity": [[s,a], ...],
                         "unit_distance": 2 x smallest spacing, "relative": true},
   "camera": {"azimuth": 30, "elevation": 20, "roll": 0, "zoom": 1.0},
   grids only: "level0_resolution": 128, "absorption": 1, "scattering": [0,0,0]}
A light's "radius" is its size, for the filtered method's soft shadows: the apparent
diameter in degrees of a directional light, the radius in world units of a point or spot
light (0: hard shadows).
"ambient_occlusion" (volumes): the intensity of an even white ambient light that reaches
each point through the transmittance averaged over the directions within
"ambient_occlusion_radius" (world units; 0: a twentieth of the volume's diagonal).
A light's "relative" (default false) gives its position and focal point as fractions of
the volume's bounding box (0..1 inside, outside beyond); a light without a position or
focal point gets the default above, always relative. A transfer function's "relative"
(default true) gives its scalars as fractions of the scalar range. Without lights, three
coloured lights are used (a warm key, a cool fill and a white rim light). Scalars are the
active point scalars or the first point array, else the cell scalars or the first cell
array (cell data are lit as point data, each point the mean of its cells); an array of
several components is lit by its magnitude ("component": -1) or the component given.
Without a transfer function (or without its "color" or "opacity" list) the default one
starts above the background: opacity is 0 up to Otsu's threshold of the scalar histogram (the value
that best separates air around a scan from the object) and rises above it, colours from
warm to white. The camera frames the points whose opacity is above 0 (the object, not
the empty box around it); "zoom" scales from there. "side_by_side" writes the same view twice
side by side, lit with local shading only (left) and with the illumination (right), each
half labelled unless "labels" is false.
)";
}

[[noreturn]] void Fail(const std::string& message)
{
  throw Failure(message);
}

std::string Lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool EndsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() &&
    s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

namespace
{
// The number in text, or a Failure.
double ParseNumber(const std::string& text)
{
  try
  {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v))
    {
      throw std::invalid_argument(text);
    }
    return v;
  }
  catch (const std::exception&)
  {
    Fail("'" + text + "' is not a number");
  }
}

// The JSON object of a settings file, or a Failure.
json ReadSettings(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
  {
    Fail("cannot open the settings file " + path);
  }
  try
  {
    json parsed = json::parse(in);
    if (!parsed.is_object())
    {
      Fail("the settings file " + path + " must hold a JSON object");
    }
    return parsed;
  }
  catch (const json::exception& e)
  {
    Fail("the settings file " + path + " is not valid JSON: " + e.what());
  }
}
}

Options ParseArguments(int argc, char* argv[])
{
  Options o;
  auto next = [&](int& i) -> std::string
  {
    if (i + 1 >= argc)
    {
      Fail(std::string("option ") + argv[i] + " needs a value");
    }
    return argv[++i];
  };
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h")
    {
      std::cout << Usage;
      std::exit(0);
    }
    else if (a == "--config")
    {
      o.Config.update(ReadSettings(next(i)));
    }
    else if (a == "--output" || a == "--method")
    {
      o.Config[a.substr(2)] = next(i);
    }
    else if (a == "--scale")
    {
      o.Config["resolution_scale"] = ParseNumber(next(i));
    }
    else if (a == "--size")
    {
      const double w = ParseNumber(next(i));
      const double h = ParseNumber(next(i));
      o.Config["image_size"] = { w, h };
    }
    else if (a == "--phantom")
    {
      o.Phantom = next(i);
    }
    else if (a == "--dims")
    {
      o.PhantomDims = static_cast<int>(ParseNumber(next(i)));
    }
    else if (!a.empty() && a[0] == '-')
    {
      Fail("unknown option " + a + " (see --help)");
    }
    else if (o.Input.empty())
    {
      o.Input = a;
    }
    else
    {
      Fail("more than one volume given (" + o.Input + ", " + a + ")");
    }
  }
  return o;
}

}
