// Portable atan and atan2: math.rs's `atan` and `atan2` beside this file, line for line (the same
// constants, the same order of operations; division through the exact arithmetic's `fdiv`), so that
// on the exact compute path (NoContraction) they return the CPU's bits. Cephes' atanf and atan2f.

const ATAN_PIO2: f32 = 1.5707963267948966;
const ATAN_PIO4: f32 = 0.7853981633974483;
const ATAN_PI: f32 = 3.141592653589793;

fn p_atan(x: f32) -> f32 {
    let negative = x < 0.0;
    var a = abs(x);
    var y = 0.0;
    if a > 2.414213562373095 {
        y = ATAN_PIO2;
        a = -fdiv(1.0, a);
    } else if a > 0.4142135623730950 {
        y = ATAN_PIO4;
        a = fdiv(a - 1.0, a + 1.0);
    }
    let z = a * a;
    y += (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1) * z * a + a;
    return select(y, -y, negative);
}

fn p_atan2(y: f32, x: f32) -> f32 {
    if x == 0.0 {
        if y < 0.0 {
            return -ATAN_PIO2;
        }
        if y == 0.0 {
            return 0.0;
        }
        return ATAN_PIO2;
    }
    if y == 0.0 {
        return select(0.0, ATAN_PI, x < 0.0);
    }
    var w = 0.0;
    if !(x > 0.0) {
        w = select(ATAN_PI, -ATAN_PI, y < 0.0);
    }
    return w + p_atan(fdiv(y, x));
}
