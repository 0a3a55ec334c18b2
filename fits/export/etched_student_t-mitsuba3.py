# stfit export 0.2.0: sample 'etched', student-t, rmse sqrt(L) 0.0066 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: student-t alpha 0.44913583584205224 gamma 2.591938662304212, eta 1.51, separable masking, orders single; the fit's scale 0.9996668759082551 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0350 over the sphere of directions, 0.0620 over the measurement grid
# sensitivity: alpha = 0.426881: rmse grows 5.999e-1 sqrt(L) per unit; change for +10% rmse 2.672e-2
etched_student_t = {
    'type': 'roughdielectric',
    'distribution': 'ggx',
    'alpha': 0.42688074139932547,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
