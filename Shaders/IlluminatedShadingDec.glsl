// VolumetricIllumination (vtkIlluminatedVolumeMapper): declarations placed before
// VTK's own //VTK::Shading::Dec. The custom uniforms volillum_* are declared by VTK
// from the volume's shader property.

// Dataset-space position of a sample given in volume texture coordinates.
vec3 volillumDatasetPosition(vec3 texPos)
{
  vec4 p = in_textureDatasetMatrix[0] * vec4(texPos, 1.0);
  return p.xyz / p.w;
}

// Light arriving at the sample, read from the illumination volume (its own texture and
// resolution, trilinear).
vec3 volillumIllumination(vec3 texPos)
{
  vec4 p = vec4(volillumDatasetPosition(texPos), 1.0);
  vec3 tc =
    vec3(dot(volillum_toIlluminationX, p), dot(volillum_toIlluminationY, p), dot(volillum_toIlluminationZ, p));
  return texture3D(volillum_illumination, tc).rgb;
}

// Uniform random number in [0, 1) from a pixel position (ray-start jitter).
float volillumRandom(vec2 pixel)
{
  return fract(sin(dot(pixel, vec2(12.9898, 78.233))) * 43758.5453);
}

// Gradient-based Phong factor Ia + Id + Is (eq. 3 of the unstructured-grid lighting
// paper) for a headlight; 1 when gradient shading is off.
float volillumPhong(vec3 texPos, vec3 rayStep)
{
  if (volillum_gradientShading == 0)
  {
    return 1.0;
  }
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

//VTK::Shading::Dec
