"""Unity-ratio spur gearbox (SPEC 6.1): exported from gearrotor for ROSS 3.x (gearrotor export --to ross-python).

Units SI. Bearing and seal tables are the coefficients gearrotor assembles (fluid-film
bearings solved at the tables' speeds); ROSS interpolates them by PCHIP, gearrotor
linearly: results agree at the table speeds."""

import numpy as np
import ross as rs

mat_0 = rs.Material(name='steel', rho=7890.0, E=211000000000.0, G_s=81153846153.84615)
mass_only = rs.Material(name="mass_only", rho=1.0, E=1.0, G_s=1.0)  # placeholder

# shaft 'shaft1': 20 elements, nodes 0..20
shaft_0 = []
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=0, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=1, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=2, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=3, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=4, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=5, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=6, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=7, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=8, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=9, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=10, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=11, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=12, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=13, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=14, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=15, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=16, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=17, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=18, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_0.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=19, shear_method_calc='cowper', alpha=0.0, beta=0.0))
disks_0 = []
# the gear has no disk in gearrotor: ROSS needs a (vanishing) inertia
gear_0 = rs.GearElement(n=10, m=2.2754618421803937e-08, Id=5.119789144905886e-12, Ip=1.0239578289811772e-11, n_teeth=30, pitch_diameter=0.22, pr_angle=0.349, helix_angle=0.0)
disks_0.append(gear_0)
bearings_0 = []
points_0 = []
bearings_0.append(rs.BearingElement(n=0, kxx=10000000.0, kxy=0.0, kyx=0.0, kyy=30000000.0, cxx=17500.0, cxy=0.0, cyx=0.0, cyy=17500.0, tag='S1-B1'))
bearings_0.append(rs.BearingElement(n=20, kxx=10000000.0, kxy=0.0, kyx=0.0, kyy=30000000.0, cxx=17500.0, cxy=0.0, cyx=0.0, cyy=17500.0, tag='S1-B2'))
rotor_0 = rs.Rotor(shaft_0, disks_0, bearings_0, point_mass_elements=points_0, tag='shaft1')

# shaft 'shaft2': 20 elements, nodes 0..20
shaft_1 = []
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=0, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=1, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=2, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=3, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=4, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=5, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=6, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=7, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=8, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=9, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=10, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=11, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=12, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=13, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=14, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=15, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=16, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=17, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=18, shear_method_calc='cowper', alpha=0.0, beta=0.0))
shaft_1.append(rs.ShaftElement(L=0.051000000000000004, idl=0.0, odl=0.06, material=mat_0, n=19, shear_method_calc='cowper', alpha=0.0, beta=0.0))
disks_1 = []
# the gear has no disk in gearrotor: ROSS needs a (vanishing) inertia
gear_1 = rs.GearElement(n=10, m=2.2754618421803937e-08, Id=5.119789144905886e-12, Ip=1.0239578289811772e-11, n_teeth=30, pitch_diameter=0.22, pr_angle=0.349, helix_angle=0.0)
disks_1.append(gear_1)
bearings_1 = []
points_1 = []
bearings_1.append(rs.BearingElement(n=0, kxx=10000000.0, kxy=0.0, kyx=0.0, kyy=30000000.0, cxx=17500.0, cxy=0.0, cyx=0.0, cyy=17500.0, tag='S2-B1'))
bearings_1.append(rs.BearingElement(n=20, kxx=10000000.0, kxy=0.0, kyx=0.0, kyy=30000000.0, cxx=17500.0, cxy=0.0, cyx=0.0, cyy=17500.0, tag='S2-B2'))
rotor_1 = rs.Rotor(shaft_1, disks_1, bearings_1, point_mass_elements=points_1, tag='shaft2')

rotor = rs.MultiRotor(rotor_0, rotor_1, coupled_nodes=(10, 10), gear_mesh_stiffness=30000000.0, orientation_angle=-0.5, mesh_damping_ratio=0.0)

SPEED = 680.6784082777884  # rad/s, the model's reference shaft (6500 rpm)

if __name__ == "__main__":
    modal = rotor.run_modal(speed=SPEED)
    print("damped frequency (Hz), log dec")
    for wd, ld in zip(modal.wd, modal.log_dec):
        print(f"{wd / 2 / np.pi:12.4f} {ld:10.4f}")
