# stfit export 0.2.0: sample 'frosted', student-t, rmse sqrt(L) 0.0094 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: student-t alpha 0.20016296817464857 gamma 3.010287782901894, eta 1.51, separable masking, orders single; the fit's scale 0.999107524728862 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0529 over the sphere of directions, 0.0840 over the measurement grid
# sensitivity: alpha = 0.188923: rmse grows 1.907e0 sqrt(L) per unit; change for +10% rmse 1.270e-2
frosted_student_t = {
    'type': 'roughdielectric',
    'distribution': 'ggx',
    'alpha': 0.1889232014354401,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
