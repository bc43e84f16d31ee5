// The Whitted classic for POV-Ray 3.7: the same scene as scenes/whitted-classic.toml
// (camera, lights, materials, colours, z up). Render with povray_whitted.sh, or
//   povray +Iwhitted_classic.pov +W800 +H600 +A0.3 +R3 +WT2 +Owhitted.png
//
// octsolid's Phong model and POV-Ray's finish are matched term by term:
//   octsolid  (1 - kr) (ka Ia C + sum I (kd C N.L + ks (R.V)^n)) + kr reflected
//   POV-Ray   ambient A C Ia + sum I (diffuse D C N.L + phong P (R.V)^phong_size)
//             + reflection kr reflected
// so A = (1 - kr) ka, D = (1 - kr) kd, P = (1 - kr) ks, phong_size = n.
// Colours are linear (assumed_gamma 1); the PNG is written sRGB-encoded, as octsolid's.

#version 3.7;

global_settings {
    assumed_gamma 1.0
    ambient_light rgb <1, 1, 1>
    max_trace_level 6           // the primary ray + octsolid's max_depth = 5
    adc_bailout 1/255           // the default, and the scene's cutoff
}

// A scene that includes this file may declare these first (turned_classic.pov).
#ifndef (Eye) #declare Eye = <3.4, -5.6, 2.9>; #end
#ifndef (Target) #declare Target = <0, 0, -0.35>; #end
#ifndef (FovY) #declare FovY = 38; #end          // vertical, degrees, as octsolid's camera
#ifndef (FloorHalf) #declare FloorHalf = 3.9; #end
#ifndef (Turn) #declare Turn = 0; #end           // the part turned about z, degrees
#declare Aspect = image_width / image_height;

camera {
    perspective
    location Eye
    right -x * Aspect           // right-handed: octsolid's world as it is
    up y
    direction z
    sky z
    angle 2 * degrees(atan(tan(radians(FovY / 2)) * Aspect))   // POV's angle is horizontal
    look_at Target
}

background { color rgb <0.45, 0.62, 0.85> }

light_source { <4, -3, 6> color rgb <0.75, 0.75, 0.75> }
light_source { <-5, -4, 4> color rgb <0.35, 0.35, 0.35> }

// The classic CSG part: ka 0.15, kd 0.75, ks 0.4, shininess 40, kr 0.1.
#declare PartKr = 0.1;
difference {
    intersection {
        box { <-1, -1, -1>, <1, 1, 1> }
        sphere { <0, 0, 0>, 1.3 }
    }
    cylinder { <-1.5, 0, 0>, <1.5, 0, 0>, 0.6 }
    cylinder { <0, -1.5, 0>, <0, 1.5, 0>, 0.6 }
    cylinder { <0, 0, -1.5>, <0, 0, 1.5>, 0.6 }
    pigment { color rgb <0.85, 0.42, 0.16> }
    finish {
        ambient (1 - PartKr) * 0.15
        diffuse (1 - PartKr) * 0.75
        phong (1 - PartKr) * 0.4
        phong_size 40
        reflection { PartKr }
    }
    rotate <0, 0, Turn>
}

// The floor: checker cubes of 0.6 (POV's checker, like octsolid's, is the parity of
// floor(x) + floor(y) + floor(z): the cube at the origin takes the first colour);
// ka 0.15, kd 0.75, no highlight, kr 0.35.
#declare FloorKr = 0.35;
box {
    <-FloorHalf, -FloorHalf, -1.2>, <FloorHalf, FloorHalf, -1.0>
    pigment { checker color rgb <0.9, 0.85, 0.2> color rgb <0.75, 0.1, 0.1> scale 0.6 }
    finish {
        ambient (1 - FloorKr) * 0.15
        diffuse (1 - FloorKr) * 0.75
        reflection { FloorKr }
    }
}
