# stfit export 0.2.0: sample 'frosted', beckmann, rmse sqrt(L) 0.1130 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: beckmann alpha 0.21829845077431576, eta 1.51, separable masking, orders single; the fit's scale 1.00844442304944 is a calibration factor, not applied
# Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0002 over the sphere of directions, 0.0001 over the measurement grid
# sensitivity: alpha = 0.218298: rmse grows 2.112e0 sqrt(L) per unit; change for +10% rmse 3.785e-5
frosted_beckmann = {
    'type': 'roughdielectric',
    'distribution': 'beckmann',
    'alpha': 0.21829845077431576,
    'int_ior': 1.51,
    'ext_ior': 1.0,
}
