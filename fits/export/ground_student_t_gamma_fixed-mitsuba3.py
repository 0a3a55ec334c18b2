# stfit export 0.2.0: sample 'ground', student-t (gamma = 3), rmse sqrt(L) 0.1168 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: student-t alpha 0.3752921994724744 gamma 3 (held fixed), eta 1.51, separable masking, orders single; the fit's scale 0.9129629689907185 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0458 over the sphere of directions, 0.0778 over the measurement grid
# sensitivity: alpha = 0.351562: rmse grows 7.601e-1 sqrt(L) per unit; change for +10% rmse 2.758e-2
ground_student_t_gamma_fixed = {
    'type': 'roughdielectric',
    'distribution': 'ggx',
    'alpha': 0.35156196881501534,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
