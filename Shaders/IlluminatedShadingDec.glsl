// VolumetricIllumination (vtkIlluminatedVolumeMapper): declarations placed before
// VTK's own //VTK::Shading::Dec. The custom uniforms volillum_* are declared by VTK
// from the volume's shader property. The mapper prepends
// "#define VOLILLUM_GRADIENT_SHADING" when gradient shading is on, so that a disabled
// feature costs nothing per sample (a branch on a uniform may still run both sides).

// Rows of the affine map from volume texture coordinates to illumination texture
// coordinates: the illumination's map from dataset positions (uniforms) composed with VTK's
// texture-to-dataset matrix (affine for image data), once per fragment.
vec4 volillumToIllumination[3];

void volillumInitialize()
{
  volillumToIllumination[0] = volillum_toIlluminationX * in_textureDatasetMatrix[0];
  volillumToIllumination[1] = volillum_toIlluminationY * in_textureDatasetMatrix[0];
  volillumToIllumination[2] = volillum_toIlluminationZ * in_textureDatasetMatrix[0];
}

// Light arriving at the sample, read from the illumination volume (its own texture and
// resolution, trilinear).
vec3 volillumIllumination(vec3 texPos)
{
  vec4 p = vec4(texPos, 1.0);
  vec3 tc = vec3(
    dot(volillumToIllumination[0], p), dot(volillumToIllumination[1], p), dot(volillumToIllumination[2], p));
  return texture3D(volillum_illumination, tc).rgb;
}

// Uniform random number in [0, 1) from a pixel position (ray-start jitter).
float volillumRandom(vec2 pixel)
{
  return fract(sin(dot(pixel, vec2(12.9898, 78.233))) * 43758.5453);
}

#ifdef VOLILLUM_GRADIENT_SHADING
// Gradient-based Phong factor Ia + Id + Is (eq. 3 of the unstructured-grid lighting
// paper) for a headlight.
float volillumPhong(vec3 texPos, vec3 rayStep)
{
  vec3 g;
  vec3 dx = vec3(in_cellStep[0].x, 0.0, 0.0);
  vec3 dy = vec3(0.0, in_cellStep[0].y, 0.0);
  vec3 dz = vec3(0.0, 0.0, in_cellStep[0].z);
  g.x = texture3D(in_volume[0], texPos + dx).r - texture3D(in_volume[0], texPos - dx).r;
  g.y = texture3D(in_volume[0], texPos + dy).r - texture3D(in_volume[0], texPos - dy).r;
  g.z = texture3D(in_volume[0], texPos + dz).r - texture3D(in_volume[0], texPos - dz).r;
  g /= in_cellSpacing[0];
  vec4 phong = volillum_phong;
  if (length(g) < 1e-6)
  {
    // No surface orientation: ambient plus the diffuse term of an isotropic medium.
    return phong.x + phong.y;
  }
  vec3 view = (in_textureDatasetMatrix[0] * vec4(rayStep, 0.0)).xyz;
  float cosine = abs(dot(normalize(g), normalize(view)));
  return phong.x + phong.y * cosine + phong.z * pow(cosine, phong.w);
}
#endif

//VTK::Shading::Dec
