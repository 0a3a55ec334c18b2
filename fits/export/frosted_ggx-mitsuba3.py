# stfit export 0.2.0: sample 'frosted', ggx, rmse sqrt(L) 0.0845 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: ggx alpha 0.1901288243200893, eta 1.51, separable masking, orders single; the fit's scale 0.9997120509270278 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0000 over the sphere of directions, 0.0000 over the measurement grid
# sensitivity: alpha = 0.190129: rmse grows 1.807e0 sqrt(L) per unit; change for +10% rmse - (the mapping is exact to rounding)
frosted_ggx = {
    'type': 'roughdielectric',
    'distribution': 'ggx',
    'alpha': 0.1901288243200893,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
