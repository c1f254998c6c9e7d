    // VolumetricIllumination (vtkIlluminatedVolumeMapper): front-to-back compositing where
    // each sample's transfer-function colour is scaled by ambient + diffuse x illumination
    // (with an exposure, 1 - exp(-exposure x that)), up to the brightest displayable colour: a composited colour then never exceeds its
    // opacity, as parallel compositing needs (IceT blends premultiplied 8-bit colours, which
    // wrap around past 1: a saturated channel turned dark).
    if (!g_skip)
    {
      vec4 scalar = texture3D(in_volume[0], g_dataPos);
      scalar.r = scalar.r * in_volume_scale[0].r + in_volume_bias[0].r;
      scalar = vec4(scalar.r);
      g_srcColor = vec4(0.0);
      g_srcColor.a = computeOpacity(scalar);
      if (g_srcColor.a > 0.0)
      {
        g_srcColor = computeColor(scalar, g_srcColor.a);
        vec3 light = volillum_diffuse * volillumIllumination(g_dataPos);
#ifdef VOLILLUM_GRADIENT_SHADING
        light *= volillumPhong(g_dataPos, g_dirStep);
#endif
        vec3 shade = volillum_ambient + light;
#ifdef VOLILLUM_EXPOSURE
        shade = 1.0 - exp(-volillum_exposure * shade);
#endif
        g_srcColor.rgb = min(g_srcColor.rgb * shade, vec3(1.0)) * g_srcColor.a;
        g_fragColor = (1.0 - g_fragColor.a) * g_srcColor + g_fragColor;
      }
    }
