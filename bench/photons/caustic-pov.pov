// The glass-ball caustic of bench/photons/caustic.txt for POV-Ray 3.7
// (scripts/photon-povray.py sets COUNT, the photons emitted towards the
// ball; 0: no photon pass).
#version 3.7;
#ifndef (COUNT) #declare COUNT = 100000; #end
global_settings {
  assumed_gamma 1.0
  max_trace_level 10
  #if (COUNT > 0) photons { count COUNT autostop 0 jitter 0.4 } #end
}
camera { location <0, 3.2, -7> look_at <0, 0.4, 0> right x*4/3 angle 48 }
light_source { <1.5, 5, -0.5> color rgb <1, 1, 1> * 0.3
  photons { refraction on reflection off } }
plane { y, 0 pigment { color rgb <0.85, 0.8, 0.7> } finish { diffuse 1 ambient 0 } }
sphere { <0, 1, 0>, 1
  pigment { color rgbf <1, 1, 1, 1> }
  finish { diffuse 0 ambient 0 specular 0 reflection 0 }
  interior { ior 1.5 }
  photons { target refraction on reflection off collect off } }
