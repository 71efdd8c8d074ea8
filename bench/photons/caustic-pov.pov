// The glass-ball caustic of bench/photons/caustic.txt for POV-Ray 3.7
// (scripts/photon-povray.py sets COUNT, the photons shot towards the
// ball; 0: no photon pass, and then POV-Ray casts no shadow through the
// transparent ball). glint's file is z-up: its (x, y, z) is (x, z, y) here.
// The script writes Radiance .hdr (+FH): linear values, never clamped.
#version 3.7;
#ifndef (COUNT) #declare COUNT = 100000; #end
// GATHER: the most photons one estimate uses (POV-Ray's default, 100,
// unless set on the command line, e.g. Declare=GATHER=1000).
#ifndef (GATHER) #declare GATHER = 100; #end
global_settings {
  assumed_gamma 1.0
  max_trace_level 10
  #if (COUNT > 0) photons { count COUNT autostop 0 jitter 0.4 gather 20, GATHER } #end
}
// angle 48 over right 4/3: glint's lens_W= 0.8904 (2 tan 24 deg), lens_H= 0.6678.
camera { location <0, 3.2, -7> look_at <0, 0.4, 0> right x*4/3 angle 48 }
// No fade: POV-Ray's direct light and its photons do not fall off with
// distance. glint's framework direct light does not either, but its
// photons do (1/d^2): its caustic is about 28 times dimmer (d^2 is 29).
light_source { <1.5, 5, 0.5> color rgb <1, 1, 1> * 0.3
  photons { refraction on reflection off } }
plane { y, 0 pigment { color rgb <0.85, 0.8, 0.7> } finish { diffuse 1 ambient 0 } }
sphere { <0, 1, 0>, 1
  pigment { color rgbf <1, 1, 1, 1> }
  finish { diffuse 0 ambient 0 specular 0 reflection 0 }
  interior { ior 1.5 }
  photons { target refraction on reflection off collect off } }
