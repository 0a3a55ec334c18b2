# stfit export 0.2.0: sample 'etched', student-t (gamma = 3), rmse sqrt(L) 0.0228 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: student-t alpha 0.46000541246485577 gamma 3 (held fixed), eta 1.51, separable masking, orders single; the fit's scale 1.0027222597226277 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0473 over the sphere of directions, 0.0824 over the measurement grid
# sensitivity: alpha = 0.428827: rmse grows 6.054e-1 sqrt(L) per unit; change for +10% rmse 3.583e-2
etched_student_t_gamma_fixed = {
    'type': 'roughdielectric',
    'distribution': 'ggx',
    'alpha': 0.4288265660100779,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
