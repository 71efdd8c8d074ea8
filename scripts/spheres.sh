# Sourced by the benchmark scripts (needs $work, the folder to write into).
# spheres N [pov]: N random diffuse spheres in a 10-unit box (radius ~ N^-1/3:
# the cloud looks alike at every N), a floor and one point light;
# deterministic. With "pov", the same scene for POV-Ray 3.7 (the camera
# written as in ../shared/bench/povray: z up, the framework's lens).
spheres() {
  local ext=txt
  [[ ${2:-} == pov ]] && ext=pov
  awk -v n="$1" -v pov="${2:-}" 'BEGIN {
    srand(42); r = 2.5 * n ^ (-1 / 3)
    if (pov) {
      print "#version 3.7;\nglobal_settings { assumed_gamma 1.0 max_trace_level 10 adc_bailout 0 }"
      print "#default { finish { ambient 0 diffuse 0 } }"
      print "#declare CamN = vnormalize(<0, 1, -0.25>);\n#declare CamDx = vnormalize(vcross(CamN, z));"
      print "camera { perspective location <0, -14, 6> direction CamN right CamDx * 1.0 up vcross(CamDx, CamN) * 0.75 }"
      print "background { rgb <0.6, 0.7, 0.9> }\nlight_source { <6, -10, 16> rgb 1 }"
      print "plane { z, 0 texture { pigment { rgb 0.8 } finish { diffuse 0.8 } } }"
    } else {
      print "background\n top= 0.6 0.7 0.9\nend"
      print "camera\n O= 0 -14 6\n N= 0 1 -0.25\n lens_W= 1.0\n lens_H= 0.75\n image_W= 1024\n image_H= 768\nend"
      print "light point\n O= 6 -10 16\n color= 1 1 1\nend"
      print "primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.8\nend"
    }
    for (i = 0; i < n; i++) {
      x = 10 * rand() - 5; y = 10 * rand() - 5; z = 10 * rand() + 0.5
      cr = rand(); cg = rand(); cb = rand()
      if (pov)
        printf "sphere { <%.5f, %.5f, %.5f>, %.5f texture { pigment { rgb <%.3f, %.3f, %.3f> } finish { diffuse 0.9 } } }\n",
          x, y, z, r, cr, cg, cb
      else
        printf "primitive sphere\n O= %.5f %.5f %.5f\n R= %.5f\n color= %.3f %.3f %.3f\n diff= 0.9\nend\n",
          x, y, z, r, cr, cg, cb
    }
  }' > "$work/spheres_$1.$ext"
}
