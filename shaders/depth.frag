// isoterra — depth only: the still frame's pre-pass (app/render/render.c)
// lays the nearest surface's depth, so the shading pass runs the terrain's
// fragment shader once a pixel instead of once per layer drawn over it.
void main()
{
}
