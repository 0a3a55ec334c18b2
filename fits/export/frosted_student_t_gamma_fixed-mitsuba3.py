# stfit export 0.2.0: sample 'frosted', student-t (gamma = 3), rmse sqrt(L) 0.0094 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: student-t alpha 0.2000964969655234 gamma 3 (held fixed), eta 1.51, separable masking, orders single; the fit's scale 0.9990759971276719 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0526 over the sphere of directions, 0.0835 over the measurement grid
# sensitivity: alpha = 0.188926: rmse grows 1.906e0 sqrt(L) per unit; change for +10% rmse 1.263e-2
frosted_student_t_gamma_fixed = {
    'type': 'roughdielectric',
    'distribution': 'ggx',
    'alpha': 0.18892584997071818,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
