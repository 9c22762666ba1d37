"""The effects of the independent simulators' corpora (indepsim3, indepsim4) and their sizes: one
draw per effect from the brief's ranges, in one order of random draws, so that a seed gives the same
plan whichever simulator reads it. The physics of each effect stays the simulator's own (its Faults).

Imported by each corpus.py as `indepsim_effects` (a name no other module of the project has)."""
import math


def draw_effect(effect, gs, rng, mesh_zeta, worn_truth):
    """A moderate size of each effect (the brief's ranges) -> (keyword arguments of the simulator's Faults,
    truth parameters). `gs`: a gear set with N, Zs, Zp, Zr, friction, backlash_sp_m, backlash_pr_m;
    `mesh_zeta`: the simulator's mesh damping ratio; `worn_truth(d)`: the truth entries of a worn profile
    of depth d beside worn_depth_m (its shape in that simulator)."""
    N = gs.N
    r2 = lambda x, q=0.05: round(round(x / q) * q, 6)  # noqa: E731
    if effect in ("sun_tooth_damage", "planet_tooth_damage", "ring_tooth_damage"):
        body = effect.split("_")[0]
        fac = r2(rng.uniform(0.5, 0.7))
        z = {"sun": gs.Zs, "planet": gs.Zp, "ring": gs.Zr}[body]
        tooth = int(rng.integers(z))
        planet = int(rng.integers(N)) if body == "planet" else 0
        f = dict(tooth_body=body, tooth_planet=planet, tooth_index=tooth, tooth_stiffness_factor=fac)
        return f, dict(tooth_stiffness_factor=fac, body=body, planet=planet, tooth=tooth)
    if effect == "pin_error":
        pins = [0.0] * N
        i = int(rng.integers(1, N))
        pins[i] = float(round(rng.choice([-1, 1]) * rng.uniform(3.0, 3.5), 2) * 1e-6)
        return dict(pin_error_m=tuple(pins)), dict(pin_error_m=pins)
    if effect == "sun_runout":
        e, ph = round(rng.uniform(3.0, 3.5), 2) * 1e-6, round(rng.uniform(0, 2 * math.pi), 3)
        return dict(sun_ecc_m=e, sun_ecc_phase_rad=ph), dict(sun_ecc_m=e, sun_ecc_phase_rad=ph)
    if effect == "carrier_runout":
        e, ph = round(rng.uniform(3.0, 3.5), 2) * 1e-6, round(rng.uniform(0, 2 * math.pi), 3)
        return (dict(carrier_ecc_m=e, carrier_ecc_phase_rad=ph),
                dict(carrier_ecc_m=e, carrier_ecc_phase_rad=ph))
    if effect == "torque_ripple":
        r, k, ph = (round(rng.uniform(0.03, 0.08), 3), float(rng.choice([1.0, 2.0])),
                    round(rng.uniform(0, 2 * math.pi), 3))
        return (dict(ripple_fraction=r, ripple_order=k, ripple_phase_rad=ph),
                dict(ripple_fraction=r, ripple_order=k, ripple_phase_rad=ph))
    if effect == "worn_profile":
        d = round(rng.uniform(3.0, 6.0), 1) * 1e-6
        return dict(worn_depth_m=d), dict(worn_depth_m=d, **worn_truth(d))
    if effect == "friction":
        fac = r2(rng.uniform(1.5, 2.0))
        return dict(friction_factor=fac), dict(friction_factor=fac,
                                                     friction_coefficient=round(gs.friction * fac, 6))
    if effect == "stiffness_level":
        fac = r2(rng.uniform(0.7, 0.8))
        return dict(stiffness_scale=fac), dict(stiffness_scale=fac)
    if effect == "damping_level":
        fac = r2(rng.uniform(2.5, 3.0), 0.25)
        return dict(damping_scale=fac), dict(damping_scale=fac, mesh_damping_ratio=round(mesh_zeta * fac, 6))
    if effect == "backlash":
        fac = 3.0
        return dict(backlash_factor=fac), dict(backlash_factor=fac, backlash_sp_m=gs.backlash_sp_m * fac,
                                                   backlash_pr_m=gs.backlash_pr_m * fac)
    if effect == "sensor_transfer_path":
        fac = r2(rng.uniform(0.6, 0.75)) if rng.random() < 0.5 else r2(rng.uniform(1.3, 1.5))
        return dict(sensor_gain_factor=fac), dict(sensor_gain_factor=fac)
    raise ValueError(effect)
