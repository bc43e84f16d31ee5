// The Whitted classic as a new user rewrote it: the part turned 20 degrees about z
// over a 40 x 40 floor, seen from closer (issue: defects found on scenes nobody here
// tuned to). octsolid's side is turned_classic.toml, its floor an .oct of its own
// domain (turned_classic_side_by_side.sh makes both pictures).
#declare Eye = <3.2, -4.2, 2.6>;
#declare Target = <0, 0, 0>;
#declare FovY = 30.5;
#declare FloorHalf = 20;
#declare Turn = 20;
#include "whitted_classic.pov"
