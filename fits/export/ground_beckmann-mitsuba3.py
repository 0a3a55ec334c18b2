# stfit export 0.2.0: sample 'ground', beckmann, rmse sqrt(L) 0.1932 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: beckmann alpha 0.4017264750073634, eta 1.51, separable masking, orders single; the fit's scale 0.8663756013723194 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0002 over the sphere of directions, 0.0004 over the measurement grid
# sensitivity: alpha = 0.401726: rmse grows 8.766e-1 sqrt(L) per unit; change for +10% rmse 1.163e-4
ground_beckmann = {
    'type': 'roughdielectric',
    'distribution': 'beckmann',
    'alpha': 0.4017264750073634,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
