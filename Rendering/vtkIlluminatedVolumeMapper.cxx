#include "vtkIlluminatedVolumeMapper.h"

#include "vtkArrayDispatch.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderProperty.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkTextureObject.h"
#include "vtkUniforms.h"
#include "vtkVolume.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "IlluminatedShadingDec.h"
#include "IlluminatedShadingImpl.h"

vtkStandardNewMacro(vtkIlluminatedVolumeMapper);
vtkCxxSetObjectMacro(vtkIlluminatedVolumeMapper, IlluminationData, vtkImageData);

namespace
{
const char* const ShadingDecTag = "//VTK::Shading::Dec";
const char* const ShadingImplTag = "//VTK::Shading::Impl";
const char* const TerminateInitTag = "//VTK::Terminate::Init";
// Sets the per-fragment illumination transform, then (volillum_jitter 1) moves each ray's first
// sample by a per-pixel random fraction of a step before the termination point is computed (VTK's
// own start is one full step in). VTK's jittering samples a Perlin-noise texture whose lattice
// shows as a regular dot pattern on surfaces; a hash of the pixel position gives white noise.
const char* const JitteredTerminateInit =
  "volillumInitialize();\n"
  "vec3 volillumJitter =\n"
  "  g_dirStep * volillum_jitter * (volillumRandom(gl_FragCoord.xy) - 1.0);\n"
  "g_rayOrigin += volillumJitter;\n"
  "g_dataPos += volillumJitter;\n"
  "//VTK::Terminate::Init";
const char* const SamplerIntDeclaration = "uniform int volillum_illumination;";
const char* const SamplerDeclaration = "uniform sampler3D volillum_illumination;";
const char* const GradientShadingDefine = "#define VOLILLUM_GRADIENT_SHADING\n";
const char* const ExposureDefine = "#define VOLILLUM_EXPOSURE\n";
const char* const UniformNames[] = { "volillum_illumination", "volillum_toIlluminationX",
  "volillum_toIlluminationY", "volillum_toIlluminationZ", "volillum_ambient", "volillum_diffuse",
  "volillum_phong", "volillum_exposure", "volillum_jitter" };

vtkDataArray* IlluminationArray(vtkImageData* image)
{
  if (!image)
  {
    return nullptr;
  }
  vtkDataArray* a = image->GetPointData()->GetArray("Illumination");
  if (!a || a->GetNumberOfComponents() != 3 || a->GetNumberOfTuples() == 0 ||
    a->GetNumberOfTuples() != image->GetNumberOfPoints())
  {
    return nullptr;
  }
  return a;
}

// Largest finite value of any channel of the illumination (0 when there is none), in one
// parallel pass over the values: a range per channel would take three serial passes, ~35 ms
// of every edit-to-frame time at a million points on a 2-core machine.
struct Largest
{
  template <typename ArrayT>
  void operator()(ArrayT* array, double& largest) const
  {
    const auto values = vtk::DataArrayValueRange<3>(array);
    vtkSMPThreadLocal<double> local(0.0);
    vtkSMPTools::For(0, values.size(),
      [&](vtkIdType begin, vtkIdType end)
      {
        double m = local.Local();
        for (vtkIdType i = begin; i < end; ++i)
        {
          const double v = static_cast<double>(values[i]);
          m = std::isfinite(v) && v > m ? v : m;
        }
        local.Local() = m;
      });
    largest = 0.0;
    for (const double m : local)
    {
      largest = std::max(largest, m);
    }
  }
};

double LargestValue(vtkDataArray* illumination)
{
  double largest = 0.0;
  if (!vtkArrayDispatch::DispatchByValueType<vtkArrayDispatch::Reals>::Execute(
        illumination, Largest{}, largest))
  {
    Largest{}(illumination, largest);
  }
  return largest;
}

// Illumination as RGBA bytes, value x scale rounded into [0, 255] (NaN and negative
// values 0); alpha unused.
struct Quantise
{
  template <typename ArrayT>
  void operator()(ArrayT* array, double scale, std::vector<unsigned char>& bytes) const
  {
    const auto tuples = vtk::DataArrayTupleRange<3>(array);
    vtkSMPTools::For(0, tuples.size(),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType i = begin; i < end; ++i)
        {
          for (int c = 0; c < 3; ++c)
          {
            const double v = static_cast<double>(tuples[i][c]) * scale;
            bytes[4 * i + c] = v > 0 ? static_cast<unsigned char>(std::min(v + 0.5, 255.0)) : 0;
          }
        }
      });
  }
};
}

//------------------------------------------------------------------------------
vtkIlluminatedVolumeMapper::vtkIlluminatedVolumeMapper() = default;

//------------------------------------------------------------------------------
vtkIlluminatedVolumeMapper::~vtkIlluminatedVolumeMapper()
{
  this->SetIlluminationData(nullptr);
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->IlluminationTexture->ReleaseGraphicsResources(window);
  this->IlluminationUploadTime = vtkTimeStamp();
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeMapper::UpdateIlluminationTexture(vtkRenderer* ren)
{
  vtkDataArray* array = IlluminationArray(this->IlluminationData);
  if (!array)
  {
    return false;
  }
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!window)
  {
    return false;
  }
  if (this->IlluminationTexture->GetContext() != window)
  {
    this->IlluminationTexture->SetContext(window);
    this->IlluminationUploadTime = vtkTimeStamp();
  }
  if (this->IlluminationUploadTime > this->IlluminationData->GetMTime() &&
    this->IlluminationUploadTime > array->GetMTime() && this->IlluminationTexture->GetHandle())
  {
    return true;
  }
  int dims[3];
  this->IlluminationData->GetDimensions(dims);
  // 8 bits per channel of the largest value: a quarter of the memory of float texels, and
  // the sampler's fastest path on software renderers.
  const double largest = LargestValue(array);
  this->IlluminationTextureScale = largest > 0 ? largest : 1.0;
  std::vector<unsigned char> bytes(4 * static_cast<size_t>(array->GetNumberOfTuples()), 0);
  if (!vtkArrayDispatch::DispatchByValueType<vtkArrayDispatch::Reals>::Execute(
        array, Quantise{}, 255.0 / this->IlluminationTextureScale, bytes))
  {
    Quantise{}(array, 255.0 / this->IlluminationTextureScale, bytes);
  }
  auto* texture = this->IlluminationTexture.Get();
  texture->SetWrapS(vtkTextureObject::ClampToEdge);
  texture->SetWrapT(vtkTextureObject::ClampToEdge);
  texture->SetWrapR(vtkTextureObject::ClampToEdge);
  texture->SetMinificationFilter(vtkTextureObject::Linear);
  texture->SetMagnificationFilter(vtkTextureObject::Linear);
  texture->SetInternalFormat(GL_RGBA8);
  if (!texture->Create3DFromRaw(dims[0], dims[1], dims[2], 4, VTK_UNSIGNED_CHAR, bytes.data()))
  {
    vtkErrorMacro("Could not upload the illumination volume as a 3D texture.");
    return false;
  }
  this->IlluminationUploadTime.Modified();
  return true;
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeMapper::SetShaderReplacements(
  vtkOpenGLShaderProperty* property, bool enable)
{
  vtkShader::ReplacementSpec spec;
  spec.OriginalValue = ShadingDecTag;
  spec.ShaderType = vtkShader::Fragment;
  spec.ReplaceFirst = true;
  const auto& replacements = property->GetAllShaderReplacements();
  const auto present = replacements.find(spec);
  // Features that are off are compiled out rather than branched over: the declarations
  // carry the defines of the mapper's state.
  const std::string declarations = std::string(this->GradientShading ? GradientShadingDefine : "") +
    (this->Exposure > 0 ? ExposureDefine : "") + IlluminatedShadingDec;
  // Adding or clearing marks the property modified, which rebuilds the shader: only do it
  // when the state changes.
  if (enable && (present == replacements.end() || present->second.Replacement != declarations))
  {
    property->AddFragmentShaderReplacement(ShadingDecTag, true, declarations, false);
    property->AddFragmentShaderReplacement(ShadingImplTag, true, IlluminatedShadingImpl, false);
    property->AddFragmentShaderReplacement(TerminateInitTag, true, JitteredTerminateInit, false);
    // Custom uniforms know no sampler type: the texture unit is set as an int uniform and
    // its declaration turned into a sampler after VTK has written it.
    property->AddFragmentShaderReplacement(SamplerIntDeclaration, false, SamplerDeclaration, false);
  }
  else if (!enable && present != replacements.end())
  {
    property->ClearFragmentShaderReplacement(ShadingDecTag, true);
    property->ClearFragmentShaderReplacement(ShadingImplTag, true);
    property->ClearFragmentShaderReplacement(TerminateInitTag, true);
    property->ClearFragmentShaderReplacement(SamplerIntDeclaration, false);
    for (const char* name : UniformNames)
    {
      property->GetFragmentCustomUniforms()->RemoveUniform(name);
    }
  }
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeMapper::SetShadingUniforms(vtkOpenGLShaderProperty* property)
{
  int dims[3];
  double origin[3], spacing[3];
  this->IlluminationData->GetDimensions(dims);
  this->IlluminationData->GetOrigin(origin);
  this->IlluminationData->GetSpacing(spacing);
  const int* extent = this->IlluminationData->GetExtent();
  // Texture coordinate of a dataset position p: in the frame of the image's axes
  // q = origin + D^-1 (p - origin) (D its direction matrix), point index (q - o) / s with
  // o the first point, texel centre at (index + 0.5) / n. One affine transform.
  vtkNew<vtkMatrix3x3> inverse;
  vtkMatrix3x3::Invert(this->IlluminationData->GetDirectionMatrix(), inverse);
  float rows[3][4];
  for (int a = 0; a < 3; ++a)
  {
    const double first = origin[a] + extent[2 * a] * spacing[a];
    const double s = 1.0 / (spacing[a] * dims[a]);
    double shift = (origin[a] - first) * s + 0.5 / dims[a];
    for (int b = 0; b < 3; ++b)
    {
      rows[a][b] = static_cast<float>(s * inverse->GetElement(a, b));
      shift -= s * inverse->GetElement(a, b) * origin[b];
    }
    rows[a][3] = static_cast<float>(shift);
  }
  vtkUniforms* u = property->GetFragmentCustomUniforms();
  u->SetUniformi("volillum_illumination", this->IlluminationTexture->GetTextureUnit());
  u->SetUniform4f("volillum_toIlluminationX", rows[0]);
  u->SetUniform4f("volillum_toIlluminationY", rows[1]);
  u->SetUniform4f("volillum_toIlluminationZ", rows[2]);
  u->SetUniformf("volillum_ambient", static_cast<float>(this->Ambient));
  // The texture holds illumination / IlluminationTextureScale.
  u->SetUniformf(
    "volillum_diffuse", static_cast<float>(this->Diffuse * this->IlluminationTextureScale));
  u->SetUniformf("volillum_exposure", static_cast<float>(this->Exposure));
  u->SetUniformf("volillum_jitter", this->JitteredRayStarts ? 1.0f : 0.0f);
  const float phong[4] = { static_cast<float>(this->PhongAmbient),
    static_cast<float>(this->PhongDiffuse), static_cast<float>(this->PhongSpecular),
    static_cast<float>(this->PhongSpecularPower) };
  u->SetUniform4f("volillum_phong", phong);
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeMapper::WithinReach(const double bounds[6])
{
  return std::all_of(bounds, bounds + 6, [](double b) { return std::abs(b) <= MaximumCoordinate; });
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeMapper::InputIsRenderable()
{
  vtkDataSet* input = this->GetInput();
  if (!input || WithinReach(input->GetBounds()))
  {
    return true;
  }
  if (this->RefusedInputTime < input->GetMTime())
  {
    vtkErrorMacro("The volume's bounds reach beyond the +-"
      << MaximumCoordinate
      << " the GPU ray caster renders (its single-precision coordinates would not advance "
         "along the rays); it is not drawn. Rescale its spacing or origin.");
    this->RefusedInputTime.Modified();
  }
  return false;
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeMapper::GPURender(vtkRenderer* ren, vtkVolume* vol)
{
  if (!this->InputIsRenderable())
  {
    return;
  }
  auto* property = vtkOpenGLShaderProperty::SafeDownCast(vol->GetShaderProperty());
  // The array the superclass renders (ParaView selects it by name, not as active scalars).
  int cellFlag = 0;
  vtkDataArray* scalars = this->GetInput()
    ? vtkAbstractMapper::GetScalars(this->GetInput(), this->ScalarMode, this->ArrayAccessMode,
        this->ArrayId, this->ArrayName, cellFlag)
    : nullptr;
  const bool supported = scalars && scalars->GetNumberOfComponents() == 1 &&
    this->GetBlendMode() == vtkVolumeMapper::COMPOSITE_BLEND;
  const bool lit = property && supported && this->UpdateIlluminationTexture(ren);
  if (property)
  {
    this->SetShaderReplacements(property, lit);
  }
  if (!lit)
  {
    this->Superclass::GPURender(ren, vol);
    return;
  }
  this->IlluminationTexture->Activate();
  this->SetShadingUniforms(property);
  this->Superclass::GPURender(ren, vol);
  this->IlluminationTexture->Deactivate();
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IlluminationData: " << this->IlluminationData << "\n";
  os << indent << "Ambient: " << this->Ambient << "\n";
  os << indent << "Diffuse: " << this->Diffuse << "\n";
  os << indent << "Exposure: " << this->Exposure << "\n";
  os << indent << "JitteredRayStarts: " << this->JitteredRayStarts << "\n";
  os << indent << "GradientShading: " << this->GradientShading << "\n";
  os << indent << "PhongAmbient: " << this->PhongAmbient << "\n";
  os << indent << "PhongDiffuse: " << this->PhongDiffuse << "\n";
  os << indent << "PhongSpecular: " << this->PhongSpecular << "\n";
  os << indent << "PhongSpecularPower: " << this->PhongSpecularPower << "\n";
}
