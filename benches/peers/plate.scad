// The perforated plate: 200 x 200 x 10 minus a 20 x 20 grid of through-holes of
// radius 3 at (5 + 10 i, 5 + 10 j), 96 segments a hole (as manifold_plate.py).
// openscad_plate.sh renders it with a time limit; -D grid=N makes a smaller plate.
grid = 20;
difference() {
    cube([10 * grid, 10 * grid, 10]);
    for (i = [0 : grid - 1], j = [0 : grid - 1])
        translate([5 + 10 * i, 5 + 10 * j, -1]) cylinder(h = 12, r = 3, $fn = 96);
}
