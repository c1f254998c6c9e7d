#include "vtkIlluminatedVolumeMapper.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderProperty.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkTextureObject.h"
#include "vtkUniforms.h"
#include "vtkVolume.h"

#include <algorithm>
#include <cmath>

#include "IlluminatedShadingDec.h"
#include "IlluminatedShadingImpl.h"

vtkStandardNewMacro(vtkIlluminatedVolumeMapper);
vtkCxxSetObjectMacro(vtkIlluminatedVolumeMapper, IlluminationData, vtkImageData);

namespace
{
const char* const ShadingDecTag = "//VTK::Shading::Dec";
const char* const ShadingImplTag = "//VTK::Shading::Impl";
const char* const TerminateInitTag = "//VTK::Terminate::Init";
// Moves each ray's first sample by a per-pixel random fraction of a step before the
// termination point is computed (VTK's own start is one full step in). VTK's jittering
// samples a Perlin-noise texture whose lattice shows as a regular dot pattern on
// surfaces; a hash of the pixel position gives white noise instead.
const char* const JitteredTerminateInit =
  "vec3 volillumJitter = g_dirStep * (volillumRandom(gl_FragCoord.xy) - 1.0);\n"
  "g_rayOrigin += volillumJitter;\n"
  "g_dataPos += volillumJitter;\n"
  "//VTK::Terminate::Init";
const char* const SamplerIntDeclaration = "uniform int volillum_illumination;";
const char* const SamplerDeclaration = "uniform sampler3D volillum_illumination;";
const char* const UniformNames[] = { "volillum_illumination", "volillum_toIlluminationX",
  "volillum_toIlluminationY", "volillum_toIlluminationZ", "volillum_ambient", "volillum_diffuse",
  "volillum_gradientShading", "volillum_phong" };

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
  vtkSmartPointer<vtkFloatArray> values = vtkFloatArray::FastDownCast(array);
  if (!values)
  {
    values = vtkSmartPointer<vtkFloatArray>::New();
    values->DeepCopy(array);
  }
  auto* texture = this->IlluminationTexture.Get();
  texture->SetWrapS(vtkTextureObject::ClampToEdge);
  texture->SetWrapT(vtkTextureObject::ClampToEdge);
  texture->SetWrapR(vtkTextureObject::ClampToEdge);
  texture->SetMinificationFilter(vtkTextureObject::Linear);
  texture->SetMagnificationFilter(vtkTextureObject::Linear);
  if (!texture->Create3DFromRaw(dims[0], dims[1], dims[2], 3, VTK_FLOAT, values->GetPointer(0)))
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
  spec.OriginalValue = ShadingImplTag;
  spec.ShaderType = vtkShader::Fragment;
  spec.ReplaceFirst = true;
  const bool present = property->GetAllShaderReplacements().count(spec) > 0;
  // Adding or clearing marks the property modified, which rebuilds the shader: only do it
  // when the state changes.
  if (enable && !present)
  {
    property->AddFragmentShaderReplacement(ShadingDecTag, true, IlluminatedShadingDec, false);
    property->AddFragmentShaderReplacement(ShadingImplTag, true, IlluminatedShadingImpl, false);
    property->AddFragmentShaderReplacement(TerminateInitTag, true, JitteredTerminateInit, false);
    // Custom uniforms know no sampler type: the texture unit is set as an int uniform and
    // its declaration turned into a sampler after VTK has written it.
    property->AddFragmentShaderReplacement(SamplerIntDeclaration, false, SamplerDeclaration, false);
  }
  else if (!enable && present)
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
  u->SetUniformf("volillum_diffuse", static_cast<float>(this->Diffuse));
  u->SetUniformi("volillum_gradientShading", this->GradientShading ? 1 : 0);
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
  os << indent << "GradientShading: " << this->GradientShading << "\n";
  os << indent << "PhongAmbient: " << this->PhongAmbient << "\n";
  os << indent << "PhongDiffuse: " << this->PhongDiffuse << "\n";
  os << indent << "PhongSpecular: " << this->PhongSpecular << "\n";
  os << indent << "PhongSpecularPower: " << this->PhongSpecularPower << "\n";
}
