# stfit export 0.2.0: sample 'ground', student-t, rmse sqrt(L) 0.0055 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: student-t alpha 0.3516738806676205 gamma 1.8003822005303516, eta 1.51, separable masking, orders single; the fit's scale 1.0022511682797117 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0228 over the sphere of directions, 0.0427 over the measurement grid
# sensitivity: alpha = 0.361701: rmse grows 7.045e-1 sqrt(L) per unit; change for +10% rmse 1.482e-2
ground_student_t = {
    'type': 'roughdielectric',
    'distribution': 'ggx',
    'alpha': 0.3617005092284471,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
