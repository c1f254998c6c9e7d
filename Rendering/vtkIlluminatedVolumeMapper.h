/**
 * @class vtkIlluminatedVolumeMapper
 * @brief GPU ray-cast volume mapper that shades every sample with an illumination volume.
 *
 * The illumination volume (a vtkImageData with the 3-component point array
 * "Illumination", as the VolumetricIllumination filters produce) is uploaded as the
 * mapper's own 3D texture at its own resolution and sampled trilinearly. Texels hold 8 bits
 * per channel of the volume's largest value (4 bytes per voxel; steps of 1/255 of the
 * brightest light, below what an 8-bit display shows of a colour shaded with it). Each sample's
 * colour is the transfer-function colour x (Ambient + Diffuse x illumination) (or, with an
 * Exposure, a curve of it that approaches the colour itself), optionally
 * times a gradient-based Phong factor for a headlight (eq. 3 of the unstructured-grid
 * lighting paper), up to 1 per channel (as VTK's own shading), then composited front to
 * back as usual. A composited colour then never exceeds its opacity, which parallel
 * compositing needs: IceT blends each process's image as premultiplied 8-bit colours, and a
 * channel brighter than its opacity wrapped around there (saturated blue turned dark).
 *
 * The shading code replaces the //VTK::Shading::Impl tag through the volume's shader
 * property; features that are off (gradient shading) are compiled out of the shader, which
 * is rebuilt when they change, instead of branched over per sample. The texture coordinate
 * of the illumination is one affine transform of the volume's, set up once per ray. The
 * texture is bound by this mapper around each render, so the very first frame is lit (no reliance
 * on UpdateShaderEvent). Supported: one-component scalars and the composite blend mode; otherwise,
 * or without illumination data, the mapper renders as its superclass. Leave the volume property's
 * Shade off: the illumination volume replaces local lighting. Ray starts are jittered by a
 * per-pixel random fraction of a step (JitteredRayStarts) so that samples at equal depths do
 * not draw rings. The
 * illumination bounds are given in the data's coordinates.
 */
#ifndef vtkIlluminatedVolumeMapper_h
#define vtkIlluminatedVolumeMapper_h

#include "VolIllumRenderingModule.h"
#include "vtkNew.h"
#include "vtkOpenGLGPUVolumeRayCastMapper.h"

class vtkImageData;
class vtkOpenGLShaderProperty;
class vtkTextureObject;

class VOLILLUMRENDERING_EXPORT vtkIlluminatedVolumeMapper : public vtkOpenGLGPUVolumeRayCastMapper
{
public:
  static vtkIlluminatedVolumeMapper* New();
  vtkTypeMacro(vtkIlluminatedVolumeMapper, vtkOpenGLGPUVolumeRayCastMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The illumination volume: a vtkImageData with the point array "Illumination"
   * (3 components). Its resolution may differ from the rendered data's.
   */
  void SetIlluminationData(vtkImageData* illumination);
  vtkGetObjectMacro(IlluminationData, vtkImageData);
  ///@}

  ///@{
  /** Light every sample receives regardless of the illumination volume. Default 0.1. */
  vtkSetClampMacro(Ambient, double, 0.0, 10.0);
  vtkGetMacro(Ambient, double);
  ///@}

  ///@{
  /** Weight of the illumination volume. Default 1. */
  vtkSetClampMacro(Diffuse, double, 0.0, 10.0);
  vtkGetMacro(Diffuse, double);
  ///@}

  ///@{
  /**
   * How light becomes brightness. 0 (the default): each sample's colour is the transfer
   * function's colour x (Ambient + Diffuse x illumination), up to 1 per channel, the
   * illumination as computed. Above 0: the colour x (1 - exp(-Exposure x (Ambient + Diffuse x
   * illumination))), which rises as light arrives and approaches the transfer function's
   * colour, the brightness local shading gives, without passing it: well-lit material looks
   * as it does under local shading whatever the number and strength of the lights, shadowed
   * material darker, and thin material that much light crosses keeps its hue instead of
   * bleaching. The Illuminated Volume representation uses 5: the light reaching the depth a
   * viewer sees inside dense material has crossed about as much material as the view looks
   * into, so it arrives at about half strength, and 1 - exp(-5 x 0.5) is 0.92.
   */
  vtkSetClampMacro(Exposure, double, 0.0, 100.0);
  vtkGetMacro(Exposure, double);
  ///@}

  ///@{
  /**
   * Multiply the illumination by a gradient-based Phong factor for a headlight,
   * PhongAmbient + PhongDiffuse |n.v| + PhongSpecular |n.v|^PhongSpecularPower, which shows
   * surface shape. Default off.
   */
  vtkSetMacro(GradientShading, bool);
  vtkGetMacro(GradientShading, bool);
  vtkBooleanMacro(GradientShading, bool);
  vtkSetClampMacro(PhongAmbient, double, 0.0, 10.0);
  vtkGetMacro(PhongAmbient, double);
  vtkSetClampMacro(PhongDiffuse, double, 0.0, 10.0);
  vtkGetMacro(PhongDiffuse, double);
  vtkSetClampMacro(PhongSpecular, double, 0.0, 10.0);
  vtkGetMacro(PhongSpecular, double);
  vtkSetClampMacro(PhongSpecularPower, double, 1.0, 256.0);
  vtkGetMacro(PhongSpecularPower, double);
  ///@}

  ///@{
  /**
   * Start each ray a per-pixel random fraction of a step in (white noise), so that samples
   * at equal depths draw no wood-grain rings; off: every ray starts one step in, as VTK's
   * mapper does without jittering. Default on. The Illuminated Volume representation turns
   * it off for interactive frames, whose coarse steps would make the noise heavy.
   */
  vtkSetMacro(JitteredRayStarts, bool);
  vtkGetMacro(JitteredRayStarts, bool);
  vtkBooleanMacro(JitteredRayStarts, bool);
  ///@}

  void ReleaseGraphicsResources(vtkWindow* window) override;

  /**
   * Largest coordinate magnitude of a volume the mapper draws. Beyond it (an absurd spacing
   * or origin) the ray caster's single-precision positions stop advancing and a frame
   * takes minutes: the mapper reports an error and draws nothing instead.
   */
  static constexpr double MaximumCoordinate = 1e15;

  /// Whether bounds (xmin, xmax, ymin, ymax, zmin, zmax) lie within MaximumCoordinate.
  static bool WithinReach(const double bounds[6]);

protected:
  vtkIlluminatedVolumeMapper();
  ~vtkIlluminatedVolumeMapper() override;

  void GPURender(vtkRenderer* ren, vtkVolume* vol) override;

  /// False (with an error, once per input change) when the input's bounds exceed
  /// MaximumCoordinate.
  bool InputIsRenderable();

  /// Upload the illumination texture when needed; false when there is nothing to shade with.
  bool UpdateIlluminationTexture(vtkRenderer* ren);
  void SetShaderReplacements(vtkOpenGLShaderProperty* property, bool enable);
  void SetShadingUniforms(vtkOpenGLShaderProperty* property);

  vtkImageData* IlluminationData = nullptr;
  double Ambient = 0.1;
  double Diffuse = 1.0;
  double Exposure = 0.0;
  bool JitteredRayStarts = true;
  bool GradientShading = false;
  double PhongAmbient = 0.3;
  double PhongDiffuse = 0.7;
  double PhongSpecular = 0.2;
  double PhongSpecularPower = 20.0;

  vtkNew<vtkTextureObject> IlluminationTexture;
  /// Illumination per unit of the texture's normalised values (its largest value).
  double IlluminationTextureScale = 1.0;
  vtkTimeStamp IlluminationUploadTime;
  vtkTimeStamp RefusedInputTime;

private:
  vtkIlluminatedVolumeMapper(const vtkIlluminatedVolumeMapper&) = delete;
  void operator=(const vtkIlluminatedVolumeMapper&) = delete;
};

#endif
