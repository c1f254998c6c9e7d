// volillum-render: the JSON settings, the lights and the transfer functions.
#include "VolIllumRender.h"

#include "IlluminationLightList.h"

#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkLight.h"
#include "vtkPiecewiseFunction.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace volillum_render
{

std::vector<double> Numbers(const json& value, size_t count, const std::string& what)
{
  if (!value.is_array() || value.size() != count)
  {
    Fail(what + " must be a list of " + std::to_string(count) + " numbers");
  }
  std::vector<double> out;
  for (const auto& v : value)
  {
    if (!v.is_number())
    {
      Fail(what + " must be a list of " + std::to_string(count) + " numbers");
    }
    out.push_back(v.get<double>());
  }
  return out;
}

// A setting of the JSON object: fallback when absent, one error line naming the key and
// the expected type when it has another.
template <typename T>
T Setting(const json& object, const char* key, const T& fallback,
  bool (json::*isExpected)() const noexcept, const char* expected)
{
  if (!object.contains(key))
  {
    return fallback;
  }
  if (!(object[key].*isExpected)())
  {
    Fail(std::string("'") + key + "' must be " + expected);
  }
  return object[key].get<T>();
}

double Number(const json& object, const char* key, double fallback)
{
  return Setting(object, key, fallback, &json::is_number, "a number");
}

bool Flag(const json& object, const char* key, bool fallback)
{
  return Setting(object, key, fallback, &json::is_boolean, "true or false");
}

std::string Text(const json& object, const char* key, const std::string& fallback)
{
  return Setting(object, key, fallback, &json::is_string, "a string");
}

// The default lights: a warm key light above-left-front, a cool fill light from the
// right and a white rim light from behind, all outside the volume.
json DefaultLights()
{
  return json::parse(R"([
    {"type": "point", "position": [-0.6, 1.4, 1.5], "relative": true,
     "color": [1.0, 0.85, 0.6], "intensity": 1.3},
    {"type": "directional", "position": [1.5, 0.4, 0.7], "focal_point": [0.5, 0.5, 0.5],
     "relative": true, "color": [0.45, 0.6, 1.0], "intensity": 0.7},
    {"type": "directional", "position": [0.5, -0.5, -1.0], "focal_point": [0.5, 0.5, 0.5],
     "relative": true, "color": [1.0, 1.0, 1.0], "intensity": 0.4}
  ])");
}

std::vector<vtkSmartPointer<vtkLight>> BuildLights(const json& config, const double bounds[6])
{
  const json lights = config.contains("lights") ? config["lights"] : DefaultLights();
  if (!lights.is_array())
  {
    Fail("'lights' must be a list");
  }
  std::vector<vtkSmartPointer<vtkLight>> out;
  for (const auto& l : lights)
  {
    if (!l.is_object())
    {
      Fail("each light must be a JSON object");
    }
    const std::string type = Text(l, "type", "directional");
    const bool relative = Flag(l, "relative", false);
    auto place = [&](const char* key, std::vector<double> fallback)
    {
      std::vector<double> p = l.contains(key) ? Numbers(l[key], 3, key) : fallback;
      if (relative || !l.contains(key))
      {
        for (int a = 0; a < 3; ++a)
        {
          p[a] = bounds[2 * a] + p[a] * (bounds[2 * a + 1] - bounds[2 * a]);
        }
      }
      return p;
    };
    auto light = vtkSmartPointer<vtkLight>::New();
    const auto position = place("position", { 0.5, 0.5, 2.0 });
    const auto focal = place("focal_point", { 0.5, 0.5, 0.5 });
    light->SetPosition(position.data());
    light->SetFocalPoint(focal.data());
    if (type == "directional")
    {
      light->SetPositional(false);
    }
    else if (type == "point" || type == "spot")
    {
      light->SetPositional(true);
      light->SetConeAngle(type == "point" ? 180.0 : Number(l, "cone_angle", 30.0));
      light->SetExponent(Number(l, "exponent", 1.0));
    }
    else
    {
      Fail("unknown light type '" + type + "' (directional, point or spot)");
    }
    const auto color =
      l.contains("color") ? Numbers(l["color"], 3, "color") : std::vector<double>{ 1.0, 1.0, 1.0 };
    light->SetDiffuseColor(color.data());
    light->SetIntensity(Number(l, "intensity", 1.0));
    light->SetSwitch(Flag(l, "on", true));
    volillum::SetLightRadius(light, Number(l, "radius", 0.0));
    out.push_back(light);
  }
  return out;
}

// Otsu's threshold of the scalars (first component, 256 bins over the range, NaN skipped):
// the value that best separates the two classes of the histogram, for a scan the air
// around it and the object.
double OtsuThreshold(vtkDataArray* scalars, const double range[2])
{
  constexpr int bins = 256;
  const double width = range[1] > range[0] ? range[1] - range[0] : 1.0;
  std::vector<double> histogram(bins, 0.0);
  const vtkIdType n = scalars->GetNumberOfTuples();
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double v = scalars->GetComponent(i, 0);
    if (std::isfinite(v))
    {
      const int b = static_cast<int>((v - range[0]) / width * bins);
      histogram[std::min(std::max(b, 0), bins - 1)] += 1.0;
    }
  }
  double total = 0.0, weighted = 0.0;
  for (int b = 0; b < bins; ++b)
  {
    total += histogram[b];
    weighted += b * histogram[b];
  }
  double below = 0.0, belowWeighted = 0.0, best = -1.0;
  int split = 0;
  for (int b = 0; b < bins - 1; ++b)
  {
    below += histogram[b];
    belowWeighted += b * histogram[b];
    const double above = total - below;
    if (below <= 0.0 || above <= 0.0)
    {
      continue;
    }
    const double meanBelow = belowWeighted / below;
    const double meanAbove = (weighted - belowWeighted) / above;
    const double between = below * above * (meanBelow - meanAbove) * (meanBelow - meanAbove);
    if (between > best)
    {
      best = between;
      split = b;
    }
  }
  return range[0] + (split + 1) * width / bins;
}

// The default transfer function over [threshold, max]: opacity 0 below the threshold, then
// a ramp (u is the fraction of the way from the threshold to the maximum); colours from a
// warm tone to white, so that the lights' colours show on the object.
void DefaultTransferFunction(double threshold, const double range[2], vtkColorTransferFunction* ctf,
  vtkPiecewiseFunction* otf, bool color, bool opacity)
{
  const double width = range[1] > threshold ? range[1] - threshold : 1.0;
  auto at = [&](double u) { return threshold + u * width; };
  if (color)
  {
    ctf->AddRGBPoint(range[0], 0.9, 0.6, 0.45);
    ctf->AddRGBPoint(at(0.0), 0.9, 0.6, 0.45);
    ctf->AddRGBPoint(at(0.35), 0.95, 0.85, 0.75);
    ctf->AddRGBPoint(at(1.0), 1.0, 1.0, 1.0);
  }
  if (opacity)
  {
    otf->AddPoint(range[0], 0.0);
    otf->AddPoint(at(0.0), 0.0);
    otf->AddPoint(at(0.1), 0.15);
    otf->AddPoint(at(0.5), 0.5);
    otf->AddPoint(at(1.0), 0.8);
  }
}

void BuildTransferFunctions(const json& config, vtkDataArray* scalars, const double range[2],
  vtkColorTransferFunction* ctf, vtkPiecewiseFunction* otf, double& unitDistance, double minSpacing)
{
  const json tf =
    config.contains("transfer_function") ? config["transfer_function"] : json::object();
  if (!tf.is_object())
  {
    Fail("'transfer_function' must be a JSON object");
  }
  const bool relative = Flag(tf, "relative", true);
  const double width = range[1] > range[0] ? range[1] - range[0] : 1.0;
  auto scalar = [&](double s) { return relative ? range[0] + s * width : s; };
  if (!tf.contains("color") || !tf.contains("opacity"))
  {
    DefaultTransferFunction(OtsuThreshold(scalars, range), range, ctf, otf, !tf.contains("color"),
      !tf.contains("opacity"));
  }
  // The lists given: points of `count` numbers, the first a scalar.
  const auto readPoints = [&](const char* key, size_t count, const char* what,
                            const std::function<void(const std::vector<double>&)>& add)
  {
    if (!tf.contains(key))
    {
      return;
    }
    const json& points = tf[key];
    if (!points.is_array() || points.empty())
    {
      Fail(std::string("the transfer function's '") + key + "' must be a non-empty list");
    }
    for (const auto& p : points)
    {
      auto v = Numbers(p, count, what);
      v[0] = scalar(v[0]);
      add(v);
    }
  };
  readPoints("color", 4, "a colour point [s,r,g,b]",
    [&](const std::vector<double>& v) { ctf->AddRGBPoint(v[0], v[1], v[2], v[3]); });
  readPoints("opacity", 2, "an opacity point [s,a]",
    [&](const std::vector<double>& v) { otf->AddPoint(v[0], v[1]); });
  unitDistance = Number(tf, "unit_distance", 2.0 * minSpacing);
  if (!(unitDistance > 0.0))
  {
    Fail("'unit_distance' must be positive");
  }
}

}
