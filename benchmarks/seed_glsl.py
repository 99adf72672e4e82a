"""The seed's GLSL, which the moderngl peer runs (plain strings: importable without the package)."""

# The seed's Phong shaders (docs/conventions.md#where-the-rules-come-from), as written there. Both stages
# declare the same structs and uniforms ("uniform declarations identical to those in the
# vertex shader").
_DECLARATIONS = """
struct PositionalLight { vec4 ambient; vec4 diffuse; vec4 specular; vec3 position; };
struct Material { vec4 ambient; vec4 diffuse; vec4 specular; float shininess; };
uniform vec4 globalAmbient;
uniform PositionalLight light;
uniform Material material;
uniform mat4 mv_matrix;
uniform mat4 proj_matrix;
uniform mat4 norm_matrix;
"""

SEED_VERTEX_SHADER = """
#version 430
layout (location=0) in vec3 vertPos;
layout (location=1) in vec3 vertNormal;
out vec3 varyingNormal;
out vec3 varyingLightDir;
out vec3 varyingVertPos;
""" + _DECLARATIONS + """void main(void)
{   varyingVertPos = (mv_matrix * vec4(vertPos, 1.0)).xyz;
    varyingLightDir = light.position - varyingVertPos;
    varyingNormal = (norm_matrix * vec4(vertNormal, 1.0)).xyz;
    gl_Position = proj_matrix * mv_matrix * vec4(vertPos, 1.0);
}
"""

SEED_FRAGMENT_SHADER = """
#version 430
in vec3 varyingNormal;
in vec3 varyingLightDir;
in vec3 varyingVertPos;
out vec4 fragColor;
""" + _DECLARATIONS + """void main(void)
{   vec3 L = normalize(varyingLightDir);
    vec3 N = normalize(varyingNormal);
    vec3 V = normalize(-varyingVertPos);
    vec3 R = normalize(reflect(-L, N));
    float cosTheta = dot(L, N);
    float cosPhi = dot(V, R);
    vec3 ambient = ((globalAmbient * material.ambient) + (light.ambient * material.ambient)).xyz;
    vec3 diffuse = light.diffuse.xyz * material.diffuse.xyz * max(cosTheta, 0.0);
    vec3 specular = light.specular.xyz * material.specular.xyz * pow(max(cosPhi, 0.0), material.shininess);
    fragColor = vec4((ambient + diffuse + specular), 1.0);
}
"""
