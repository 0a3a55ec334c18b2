# stfit export 0.2.0: sample 'etched', beckmann, rmse sqrt(L) 0.1207 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: beckmann alpha 0.5193579495293195, eta 1.51, separable masking, orders single; the fit's scale 1.0119956915431843 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0002 over the sphere of directions, 0.0004 over the measurement grid
# sensitivity: alpha = 0.519358: rmse grows 6.671e-1 sqrt(L) per unit; change for +10% rmse 1.626e-4
etched_beckmann = {
    'type': 'roughdielectric',
    'distribution': 'beckmann',
    'alpha': 0.5193579495293195,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
