# stfit export 0.2.0: sample 'frosted', student-t, rmse sqrt(L) 0.0094 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: student-t alpha 0.20016296817464857 gamma 3.010287782901894, eta 1.51, separable masking, orders single; the fit's scale 0.999107524728862 is a calibration factor, not applied
# Cycles Glass BSDF: alpha = Roughness^2 (intern/cycles/kernel/svm/closure.h)
# Cycles Principled BSDF, white with Transmission Weight 1 and white Specular Tint: the same GGX glass closure, real dielectric Fresnel (closure.h, bsdf_microfacet.h)
# translation: fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0533 over the sphere of directions, 0.0841 over the measurement grid
# sensitivity: Roughness = 0.434648: rmse grows 1.659e0 sqrt(L) per unit; change for +10% rmse 1.472e-2
# Principled BSDF (GGX): Roughness 0.43464775932719135, fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0533 over the sphere of directions, 0.0841 over the measurement grid
import bpy

def frosted_student_t_glass():
    mat = bpy.data.materials.new("frosted_student_t_glass")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    glass = nodes.new("ShaderNodeBsdfGlass")
    glass.distribution = 'GGX'
    glass.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glass.inputs["Roughness"].default_value = 0.43464775932719135
    glass.inputs["IOR"].default_value = 1.51
    out = nodes.get("Material Output")
    mat.node_tree.links.new(glass.outputs["BSDF"], out.inputs["Surface"])
    return mat

def frosted_student_t_principled():
    mat = bpy.data.materials.new("frosted_student_t_principled")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.distribution = 'GGX'
    bsdf.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 0.43464775932719135
    bsdf.inputs["IOR"].default_value = 1.51
    bsdf.inputs["Transmission Weight"].default_value = 1.0
    bsdf.inputs["Specular Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
    return mat
