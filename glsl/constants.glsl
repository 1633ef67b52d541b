// Constants shared by the other includes.
const float PI = 3.14159265358979323846;
